// Images on the host: linear RGB float planes, EXR/PNG output, error metrics (docs/design.md §7).
#pragma once
#include <string>
#include <vector>

namespace bp {

struct ImageRGB {
  int width = 0, height = 0;
  std::vector<float> rgb;  // interleaved R,G,B, row-major, top row first
  ImageRGB() = default;
  ImageRGB(int w, int h) : width(w), height(h), rgb(std::size_t(w) * h * 3, 0.0f) {}
  float* pixel(int x, int y) { return &rgb[(std::size_t(y) * width + x) * 3]; }
  const float* pixel(int x, int y) const { return &rgb[(std::size_t(y) * width + x) * 3]; }
};

// A named layer: "" is the main image (channels R,G,B); others are written as NAME.R, NAME.G, NAME.B.
struct ImageLayer {
  std::string name;
  const ImageRGB* image;
};

// Writes float32 OpenEXR atomically (temporary file, then rename): no half-written file is left
// behind on failure. Throws std::runtime_error naming the file on failure.
void write_exr(const std::string& path, const std::vector<ImageLayer>& layers);

// Reads one layer ("" = R,G,B) of an EXR file. Throws std::runtime_error naming file and layer.
ImageRGB read_exr(const std::string& path, const std::string& layer = "");

// Names of the RGB layers in an EXR file ("" for the main one).
std::vector<std::string> exr_layer_names(const std::string& path);

// Tone-mapped sRGB PNG: scale by 2^exposure_stops, clamp to [0,1], sRGB OETF, 8 bit; non-finite
// pixels become 0. Atomic like write_exr.
void write_png(const std::string& path, const ImageRGB& image, float exposure_stops = 0.0f);

// The sRGB OETF (IEC 61966-2-1 piecewise curve) of a linear value in [0,1].
float srgb_encode(float linear);

struct ErrorMetrics {
  double rel_mse = 0.0;  // mean((I-R)^2 / (R^2 + 0.01)) over pixels and channels
  double rmse = 0.0;
  double mean_bias = 0.0;  // mean(I) - mean(R)
  double mean_abs_difference = 0.0;  // mean(|I - R|)
  double reference_mean = 0.0;       // mean(R), to state the others relative to the image level
};
// Throws std::invalid_argument if the sizes differ.
ErrorMetrics compare_images(const ImageRGB& image, const ImageRGB& reference);

}  // namespace bp

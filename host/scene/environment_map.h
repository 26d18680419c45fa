// The environment light's map on the host (--environment, docs/design.md §6): an equirectangular RGB
// image read from an EXR file, or the 1x1 map of a uniform radiance, and its packing with the
// sampling cdfs for the kernels (kernels/shared/environment_map.h owns the directions and the pdf).
#pragma once
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace bp {

// The largest map read (so its texels and cdfs, ~12 bytes per texel, fit any device): documented in
// `render --help` and the README.
constexpr int kEnvironmentMaxWidth = 8192, kEnvironmentMaxHeight = 4096;

struct EnvironmentImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // radiance, W sr^-1 m^-2, interleaved R,G,B, row-major, top row (+Y) first
  bool empty() const { return width == 0 || height == 0; }
};

// The R,G,B (alpha ignored) of an EXR file. Throws SceneError, one line naming the file: missing or
// not an EXR, no R,G,B channels, an empty image, one beyond kEnvironmentMax*, a NaN, infinite or
// negative texel.
EnvironmentImage load_environment_exr(const std::string& path);

// A uniform radiance as the 1x1 map (empty where it is black).
EnvironmentImage uniform_environment(const glm::vec3& radiance);

// Texel luminance x sin(theta of its row's centre): the weight the sampling distribution gives it.
double environment_sampling_weight(const EnvironmentImage& map, int column, int row);

// The integral of the mean of R,G,B over the sphere, W sr^-1 m^-2 sr (light selection's power).
double environment_integral(const EnvironmentImage& map);

// The map as kernels/shared/environment_map.h reads it: the marginal cdf over rows, each row's
// conditional cdf, then the texels (environment_packed_floats floats).
std::vector<float> pack_environment(const EnvironmentImage& map);

}  // namespace bp

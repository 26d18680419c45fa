// Running sums of per-pixel radiance in double (survives 1e5+ rounds without losing precision).
#pragma once
#include "image/image.h"
#include <cstdint>
#include <vector>

namespace bp {

struct Accumulator {
  int width = 0, height = 0;
  std::vector<double> sum;            // interleaved RGB sums over samples
  std::uint64_t samples_per_pixel = 0;

  Accumulator() = default;
  Accumulator(int w, int h) : width(w), height(h), sum(std::size_t(w) * h * 3, 0.0) {}
  ImageRGB mean() const {
    ImageRGB img(width, height);
    double inv = samples_per_pixel ? 1.0 / double(samples_per_pixel) : 0.0;
    for (std::size_t i = 0; i < sum.size(); ++i) img.rgb[i] = float(sum[i] * inv);
    return img;
  }
};

}  // namespace bp

// The test side's statement of the value the error estimate divides by (image/error_estimate.h):
// the smaller of a pixel and the mean of its (up to 8) neighbours, channel by channel, and the
// relMSE of per-value variances over it. Written out here, apart from the code it checks.
#pragma once
#include "image/image.h"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace bp::test {

inline double estimate_reference_value(const ImageRGB& image, int x, int y, int c) {
  double neighbours = 0.0;
  int count = 0;
  for (int ny = std::max(0, y - 1); ny <= std::min(image.height - 1, y + 1); ++ny)
    for (int nx = std::max(0, x - 1); nx <= std::min(image.width - 1, x + 1); ++nx)
      if (nx != x || ny != y) {
        neighbours += image.rgb[(std::size_t(ny) * image.width + nx) * 3 + c];
        ++count;
      }
  const double own = image.rgb[(std::size_t(y) * image.width + x) * 3 + c];
  return count ? std::min(own, neighbours / count) : own;
}

// mean over values of variance / (R̂² + 0.01), R̂ = estimate_reference_value (docs/design.md §7, §9).
inline double estimated_rel_mse_of(const ImageRGB& image, const std::vector<double>& variance) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double r = estimate_reference_value(image, x, y, c);
        sum += variance[(std::size_t(y) * image.width + x) * 3 + c] / (r * r + 0.01);
      }
  return sum / double(image.rgb.size());
}

}  // namespace bp::test

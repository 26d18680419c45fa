// Error metrics of docs/design.md §7, accumulated in double.
#include "image/image.h"

#include <cmath>
#include <stdexcept>

namespace bp {

ErrorMetrics compare_images(const ImageRGB& image, const ImageRGB& reference) {
  if (image.width != reference.width || image.height != reference.height)
    throw std::invalid_argument("compare_images: image is " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + ", reference is " +
                                std::to_string(reference.width) + "x" + std::to_string(reference.height));
  ErrorMetrics m;
  const std::size_t n = std::size_t(image.width) * image.height * 3;
  if (n == 0) return m;
  double sum_rel = 0.0, sum_sq = 0.0, sum_abs = 0.0, sum_image = 0.0, sum_reference = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = image.rgb[i], r = reference.rgb[i], d = v - r;
    sum_rel += d * d / (r * r + 0.01);
    sum_sq += d * d;
    sum_abs += std::fabs(d);
    sum_image += v;
    sum_reference += r;
  }
  m.rel_mse = sum_rel / double(n);
  m.rmse = std::sqrt(sum_sq / double(n));
  m.mean_bias = sum_image / double(n) - sum_reference / double(n);
  m.mean_abs_difference = sum_abs / double(n);
  m.reference_mean = sum_reference / double(n);
  return m;
}

}  // namespace bp

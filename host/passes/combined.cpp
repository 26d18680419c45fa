#include "passes/combined.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bp {

RoundShape round_shape(double c) {
  if (!std::isfinite(c) || c < 1e-6 || c > 1e6)
    throw std::invalid_argument("--ratio must be a number in [1e-6, 1e6] (PT samples per pixel per RB iteration)");
  RoundShape shape;
  if (c >= 1.0) shape.pt_samples = std::uint32_t(std::lround(c));
  else shape.rb_iterations = std::uint32_t(std::lround(1.0 / c));
  return shape;
}

BatchCounts CombinedPass::run(std::uint64_t first, std::uint32_t count) {
  BatchCounts pt = pt_.run(first * shape_.pt_samples, count * shape_.pt_samples);
  BatchCounts rb = rb_.run(first * shape_.rb_iterations, count * shape_.rb_iterations);
  return BatchCounts{pt.rays + rb.rays, rb.fragments, pt.nonfinite_samples + rb.nonfinite_samples};
}

std::uint32_t CombinedPass::max_batch() const {
  return std::max<std::uint32_t>(1, std::min(pt_.max_batch() / shape_.pt_samples, rb_.max_batch() / shape_.rb_iterations));
}

}  // namespace bp

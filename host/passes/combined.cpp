#include "passes/combined.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bp {

RoundShape round_shape(double c) {
  if (!std::isfinite(c) || (c != 0.0 && (c < 1e-6 || c > 1e6)))
    throw std::invalid_argument(
        "--ratio must be 0 (ray bundles alone) or a number in [1e-6, 1e6] (PT samples per pixel per RB iteration)");
  RoundShape shape;
  if (c == 0.0) shape.pt_samples = 0;
  else if (c >= 1.0) shape.pt_samples = std::uint32_t(std::lround(c));
  else shape.rb_iterations = std::uint32_t(std::lround(1.0 / c));
  return shape;
}

CombinedWeights combined_weights(std::uint32_t mode, const RoundShape& shape) {
  if (shape.pt_samples == 0) return CombinedWeights{BP_WEIGHTS_NONE, 1.0f};
  return CombinedWeights{mode, float(1.0 / shape.ratio())};
}

namespace {
void add(BatchCounts& total, const BatchCounts& c) {
  total.rays += c.rays;
  total.fragments += c.fragments;
  total.nonfinite_samples += c.nonfinite_samples;
}
}  // namespace

BatchCounts CombinedPass::run(std::uint64_t first, std::uint32_t count) {
  BatchCounts total;
  const std::uint64_t pt_max = std::max<std::uint32_t>(1, pt_.max_batch());
  const std::uint64_t pt_end = (first + count) * shape_.pt_samples;
  for (std::uint64_t s = first * shape_.pt_samples; s < pt_end;) {
    const std::uint64_t next = std::min(pt_end, (s / pt_max + 1) * pt_max);
    add(total, pt_.run(s, std::uint32_t(next - s)));
    s = next;
  }
  add(total, rb_.run(first * shape_.rb_iterations, count * shape_.rb_iterations));
  return total;
}

std::uint32_t CombinedPass::max_batch() const {
  const std::uint32_t rb = rb_.max_batch() / shape_.rb_iterations;
  if (shape_.pt_samples == 0) return std::max<std::uint32_t>(1, rb);
  return std::max<std::uint32_t>(1, std::min(pt_.max_batch() / shape_.pt_samples, rb));
}

}  // namespace bp

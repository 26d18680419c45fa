#include "image/rb_level.h"

#include <cmath>

namespace bp {

double rb_level_factor(double rb_level, double rb_variance, double pt_level, double pt_variance) {
  if (!(std::isfinite(rb_level) && rb_level > 0.0 && std::isfinite(pt_level))) return 1.0;
  if (!(std::isfinite(rb_variance) && std::isfinite(pt_variance) && rb_variance >= 0.0 && pt_variance >= 0.0))
    return 1.0;
  if (rb_variance + pt_variance <= 0.0) return 1.0;
  // M = (M_RB / Var_RB + M_PTc / Var_PTc) / (1 / Var_RB + 1 / Var_PTc), written without dividing by
  // a variance that may be 0: the weight of RB's own level is Var_PTc / (Var_RB + Var_PTc).
  const double rb_weight = pt_variance / (rb_variance + pt_variance);
  const double mean = rb_weight * rb_level + (1.0 - rb_weight) * pt_level;
  if (!(mean > 0.0)) return 1.0;
  return mean / rb_level;  // s = M / M_RB
}

RbLevel::RbLevel(std::uint64_t first_round, const Accumulator& pt, std::uint32_t pt_samples, const Accumulator& rb,
                 std::uint32_t rb_iterations, const std::optional<State>& resumed)
    : pt_accum_(pt),
      rb_accum_(rb),
      pt_scale_(1.0 / (double(pt_samples) * double(pt.width) * double(pt.height))),
      rb_scale_(1.0 / (double(rb_iterations) * double(rb.width) * double(rb.height))),
      pt_sums_(3, 0.0),
      rb_sums_(3, 0.0),
      pt_round_sums_{&pt_sums_, 1.0},
      rb_round_sums_{&rb_sums_, 1.0} {
  update_sums();
  if (resumed) {
    pt_.emplace(BatchMeansErrorEstimate::from_state(resumed->pt, 1, 1));
    rb_.emplace(BatchMeansErrorEstimate::from_state(resumed->rb, 1, 1));
  } else {  // batches of one round or more: the render loop's batches
    pt_.emplace(1, 1, 1, 1, first_round, first_round ? &pt_round_sums_ : nullptr);
    rb_.emplace(1, 1, 1, 1, first_round, first_round ? &rb_round_sums_ : nullptr);
  }
}

void RbLevel::update_sums() {
  std::array<double, 3> pt{}, rb{};
  for (std::size_t i = 0; i < rb_accum_.sum.size(); ++i) rb[i % 3] += rb_accum_.sum[i];
  for (std::size_t i = 0; i < pt_accum_.raw_sum.size(); ++i) pt[i % 3] += pt_accum_.raw_sum[i] - pt_accum_.sum[i];
  for (int c = 0; c < 3; ++c) {
    pt_sums_[std::size_t(c)] = pt[std::size_t(c)] * pt_scale_;
    rb_sums_[std::size_t(c)] = rb[std::size_t(c)] * rb_scale_;
  }
}

void RbLevel::add(std::uint64_t rounds) {
  update_sums();
  pt_->add(rounds, pt_round_sums_);
  rb_->add(rounds, rb_round_sums_);
}

std::array<double, 3> RbLevel::levels(const std::vector<double>& sums, const BatchMeansErrorEstimate& e) {
  std::array<double, 3> out{};
  for (int c = 0; c < 3; ++c)
    out[std::size_t(c)] = e.rounds() ? sums[std::size_t(c)] / double(e.rounds()) : std::nan("");
  return out;
}

std::array<double, 3> RbLevel::standard_errors(const BatchMeansErrorEstimate& e) {
  const std::vector<double> var = e.variance_of_mean();
  std::array<double, 3> out{};
  for (int c = 0; c < 3; ++c) out[std::size_t(c)] = var.empty() ? std::nan("") : std::sqrt(var[std::size_t(c)]);
  return out;
}

std::array<double, 3> RbLevel::factors() const {
  const std::array<double, 3> rb = rb_levels(), pt = pt_levels();
  const std::array<double, 3> rb_se = rb_standard_errors(), pt_se = pt_standard_errors();
  std::array<double, 3> out{};
  for (std::size_t c = 0; c < 3; ++c) out[c] = rb_level_factor(rb[c], rb_se[c] * rb_se[c], pt[c], pt_se[c] * pt_se[c]);
  return out;
}

}  // namespace bp

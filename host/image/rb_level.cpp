#include "image/rb_level.h"

#include <algorithm>
#include <cmath>

namespace bp {

double rb_level_factor(double rb_level, double rb_variance, double pt_level, double pt_variance) {
  if (!(std::isfinite(rb_level) && rb_level > 0.0 && std::isfinite(pt_level))) return 1.0;
  if (!(std::isfinite(rb_variance) && std::isfinite(pt_variance) && rb_variance >= 0.0 && pt_variance >= 0.0))
    return 1.0;
  if (rb_variance + pt_variance <= 0.0) return 1.0;
  // M = (M_RB / Var_RB + M_PTc / Var_PTc) / (1 / Var_RB + 1 / Var_PTc), written without dividing by
  // a variance that may be 0: the weight of RB's own level is Var_PTc / (Var_RB + Var_PTc).
  return rb_level_factor_weighted(rb_level, pt_level, pt_variance / (rb_variance + pt_variance));
}

double rb_level_factor_weighted(double rb_level, double pt_level, double rb_weight) {
  if (!(std::isfinite(rb_level) && rb_level > 0.0 && std::isfinite(pt_level) && std::isfinite(rb_weight))) return 1.0;
  const double mean = rb_weight * rb_level + (1.0 - rb_weight) * pt_level;
  if (!(mean > 0.0)) return 1.0;
  return mean / rb_level;  // s = M / M_RB
}

RbLevel::RbLevel(RegionGrid grid, std::uint64_t first_round, const Accumulator& pt, std::uint32_t pt_samples,
                 const Accumulator& rb, std::uint32_t rb_iterations, const std::optional<State>& resumed)
    : grid_(grid),
      pt_accum_(pt),
      rb_accum_(rb),
      pt_scale_(1.0 / double(pt_samples)),
      rb_scale_(1.0 / double(rb_iterations)),
      pt_sums_(grid.count() * 3, 0.0),
      rb_sums_(grid.count() * 3, 0.0),
      pt_round_sums_{&pt_sums_, 1.0},
      rb_round_sums_{&rb_sums_, 1.0} {
  for (std::size_t n : grid_.pixel_counts()) region_scales_.push_back(1.0 / double(n));
  update_sums();
  if (resumed) {
    pt_.emplace(BatchMeansErrorEstimate::from_state(resumed->pt, grid_.columns, grid_.rows));
    rb_.emplace(BatchMeansErrorEstimate::from_state(resumed->rb, grid_.columns, grid_.rows));
  } else {  // batches of one round or more: the render loop's batches
    pt_.emplace(grid_.columns, grid_.rows, 1, 1, first_round, first_round ? &pt_round_sums_ : nullptr);
    rb_.emplace(grid_.columns, grid_.rows, 1, 1, first_round, first_round ? &rb_round_sums_ : nullptr);
  }
}

void RbLevel::update_sums() {
  std::vector<double> pt_share(pt_accum_.raw_sum.size());
  for (std::size_t i = 0; i < pt_share.size(); ++i) pt_share[i] = pt_accum_.raw_sum[i] - pt_accum_.sum[i];
  const std::vector<double> pt = grid_.sums(pt_share), rb = grid_.sums(rb_accum_.sum);
  for (std::size_t i = 0; i < pt_sums_.size(); ++i) {
    pt_sums_[i] = pt[i] * pt_scale_ * region_scales_[i / 3];
    rb_sums_[i] = rb[i] * rb_scale_ * region_scales_[i / 3];
  }
}

void RbLevel::add(std::uint64_t rounds) {
  update_sums();
  pt_->add(rounds, pt_round_sums_);
  rb_->add(rounds, rb_round_sums_);
}

std::vector<std::array<double, 3>> RbLevel::levels(const std::vector<double>& sums, const BatchMeansErrorEstimate& e) {
  std::vector<std::array<double, 3>> out(sums.size() / 3);
  for (std::size_t i = 0; i < sums.size(); ++i)
    out[i / 3][i % 3] = e.rounds() ? sums[i] / double(e.rounds()) : std::nan("");
  return out;
}

std::vector<std::array<double, 3>> RbLevel::standard_errors(const BatchMeansErrorEstimate& e) {
  const std::vector<double> var = e.variance_of_mean();
  std::vector<std::array<double, 3>> out(std::size_t(e.state().width) * std::size_t(e.state().height));
  for (std::size_t i = 0; i < out.size() * 3; ++i) out[i / 3][i % 3] = var.empty() ? std::nan("") : std::sqrt(var[i]);
  return out;
}

std::vector<std::array<double, 3>> RbLevel::factors(const std::vector<double>& rb_weights) const {
  const auto rb = rb_levels(), pt = pt_levels(), rb_se = rb_standard_errors(), pt_se = pt_standard_errors();
  std::vector<std::array<double, 3>> out(rb.size());
  for (std::size_t r = 0; r < out.size(); ++r)
    for (std::size_t c = 0; c < 3; ++c) {
      const bool weighted = r < rb_weights.size() && std::isfinite(rb_weights[r]);
      const double factor = weighted ? rb_level_factor_weighted(rb[r][c], pt[r][c], rb_weights[r])
                                     : rb_level_factor(rb[r][c], rb_se[r][c] * rb_se[r][c], pt[r][c], pt_se[r][c] * pt_se[r][c]);
      out[r][c] = std::clamp(factor, 1.0 / kRbLevelFactorLimit, kRbLevelFactorLimit);
    }
  return out;
}

std::vector<double> RbLevel::pixel_factors(const std::vector<double>& rb_weights) const {
  const std::vector<std::array<double, 3>> target = factors(rb_weights);
  if (grid_.count() == 1) return grid_.bilinear(target);  // one factor: the field is constant
  // The centre values g_r whose bilinear field F scales each region's RB layer by its factor:
  // Σ_{p∈r} F(p) rb(p) = s_r Σ_{p∈r} rb(p), per channel. g ← g · s_r / (the region's mean factor).
  const std::vector<double> rb_sums = grid_.sums(rb_accum_.sum);
  std::vector<std::array<double, 3>> centre = target;
  std::vector<double> field = grid_.bilinear(centre);
  for (int step = 0; step < kRbLevelFieldIterations; ++step) {
    std::vector<double> scaled(field.size());
    for (std::size_t i = 0; i < field.size(); ++i) scaled[i] = field[i] * rb_accum_.sum[i];
    const std::vector<double> scaled_sums = grid_.sums(scaled);
    for (std::size_t r = 0; r < centre.size(); ++r)
      for (std::size_t c = 0; c < 3; ++c) {
        const double own = rb_sums[r * 3 + c], now = scaled_sums[r * 3 + c];
        if (own > 0.0 && now > 0.0)
          centre[r][c] = std::clamp(centre[r][c] * target[r][c] * own / now, 1.0 / kRbLevelFieldCentreLimit,
                                    kRbLevelFieldCentreLimit);
      }
    field = grid_.bilinear(centre);
  }
  return field;
}

}  // namespace bp

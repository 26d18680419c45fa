// The level of RB's share of the combined image, from both estimators (--rb-level). RB's weighted layer is smooth but its level -- the layer's mean over the pixels, per
// channel -- is noisy: every patch of an iteration moves along the same random direction, so the
// error of one iteration is the same sign over the whole image and does not average out over pixels
// (the house at 160 iterations: the image mean spreads by ±2 % between seeds). PT estimates the same
// quantity with its unweighted minus weighted estimate, (1 − w_PT)·f/p = w_RB·f/p per path, whose
// level is nearly exact (every pixel's samples are independent). So the combined image is
//
//   I = PT_w + s · RB_w,   s = M / M_RB   per channel,
//   M = (M_RB / Var_RB + M_PTc / Var_PTc) / (1 / Var_RB + 1 / Var_PTc)   (inverse-variance mean)
//
// with M_RB RB's level, M_PTc PT's level of the same share, and each variance of the mean from batch
// means over the render loop's batches (PT's rounds are independent; RB's batches of the loop's
// length are correlated, so Var_RB is if anything low and the mean leans to RB's own level). A
// ratio estimator: consistent, biased only to second order in the levels' relative noise (4e-4 at
// 2 % noise), and it takes RB's level discretisation with it. Measured: README, "The RB level from
// both estimators".
//
// --rb-level regional (docs/design.md §9, "Regional error") does the same per region of a grid
// (image/regions.h): RB's chain moves the light of whole rooms together, so its error is regional
// as well as global, and PT's estimate of RB's share in a region of thousands of pixels is still
// good to a percent or so. Each region gets its own factor s_r, its weights those of the regional
// error estimate (image/regional_error.h: inverse-variance, leaning on PT where RB's level differs
// from PT's by more than their noise, RB's discretisation bias); the image's RB layer is scaled by a
// field interpolated bilinearly between values at the regions' centres (smooth: RB's regional error
// is smooth, and a step at a block edge would show), those values chosen so that each region's mean
// of the scaled layer is exactly s_r times its own (a fixed point, kRbLevelFieldIterations
// multiplicative steps): each region's level is its inverse-variance mean, not a blend of its
// neighbours'. --rb-level corrected is the 1x1 grid.
#pragma once
#include "image/accumulator.h"
#include "image/error_estimate.h"
#include "image/regions.h"

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace bp {

// One channel's inverse-variance mean of two estimates of RB's level, as a factor on RB's own:
// M / M_RB (above). 1 (RB's own level) where the factor cannot be trusted: a variance is unknown
// (NaN: fewer than two batches) or RB's level or the mean is not positive and finite.
double rb_level_factor(double rb_level, double rb_variance, double pt_level, double pt_variance);
// The same with RB's weight in the mean given: M = w·M_RB + (1 − w)·M_PTc, as a factor M / M_RB
// (--rb-level regional: w is RegionalError's λ, from the variances of the region's luminance).
double rb_level_factor_weighted(double rb_level, double pt_level, double rb_weight);

// The factors RbLevel applies stay within [1 / limit, limit]: in a region where RB's share is nearly
// nothing (a dark corner, RB's layer a few noisy pixels) the ratio M / M_RB could be large and
// would multiply RB's per-pixel noise with it; there PT's level is off by more than RB's anyway.
constexpr double kRbLevelFactorLimit = 4.0;
// Steps of the field's fixed point: each multiplies a region's centre value by the ratio of its
// factor to its mean under the field; 16 bring every region's mean within 1e-4 of its factor on
// the houses (checked in tests/unit/test_rb_level.cpp).
constexpr int kRbLevelFieldIterations = 16;
// The field's centre values may go further than the factors: where a region's RB layer lies near
// its edge (a bright patch, a few firefly pixels), its neighbours' centres weigh there, and its own
// centre must move further for the region's mean to reach its factor (the glossy box at 8 spp: a
// region whose factor is 0.35 needed a centre below 1/4). What the field still misses is reported
// as error (image/regional_error.h).
constexpr double kRbLevelFieldCentreLimit = 16.0;

class RbLevel {
 public:
  // Tracks the levels from round `first_round`; pt and rb are the render's accumulators (pt with its
  // unweighted sums), each round adding pt_samples PT samples per pixel and rb_iterations RB
  // iterations. A resumed render passes its checkpoint's state.
  struct State {
    BatchMeansErrorEstimate::State pt, rb;  // columns x rows "images" of the regions' per-round levels
  };
  // `grid`: the regions (1x1: --rb-level corrected); a resumed state must have its size.
  RbLevel(RegionGrid grid, std::uint64_t first_round, const Accumulator& pt, std::uint32_t pt_samples,
          const Accumulator& rb, std::uint32_t rb_iterations, const std::optional<State>& resumed);

  // After a batch of the render loop (the accumulators hold rounds [0, rounds)).
  void add(std::uint64_t rounds);

  const RegionGrid& grid() const { return grid_; }
  // Per region and channel: the factor s on RB's weighted layer, the levels (the region's mean) and
  // the standard errors of their means. `rb_weights`, per region (--rb-level regional): RB's weight
  // in the inverse-variance mean, as RegionalError computes it, so that the image is the estimator
  // whose error it reports; empty, or NaN in a region: from this class's own variances.
  std::vector<std::array<double, 3>> factors(const std::vector<double>& rb_weights = {}) const;
  std::vector<std::array<double, 3>> rb_levels() const { return levels(rb_sums_, *rb_); }
  std::vector<std::array<double, 3>> pt_levels() const { return levels(pt_sums_, *pt_); }
  std::vector<std::array<double, 3>> rb_standard_errors() const { return standard_errors(*rb_); }
  std::vector<std::array<double, 3>> pt_standard_errors() const { return standard_errors(*pt_); }
  // Per pixel and channel, the factor on RB's layer: the regions' factors, bilinear between their
  // centres (one factor per channel on a 1x1 grid).
  std::vector<double> pixel_factors(const std::vector<double>& rb_weights = {}) const;
  std::uint64_t batches() const { return pt_->batches(); }
  State state() const { return State{pt_->state(), rb_->state()}; }

 private:
  // The sums over rounds of each region's and channel's level: RB's weighted layer, and PT's
  // unweighted less its weighted layer, per round (so that sums / rounds is the region's mean).
  void update_sums();
  static std::vector<std::array<double, 3>> levels(const std::vector<double>& sums, const BatchMeansErrorEstimate& e);
  static std::vector<std::array<double, 3>> standard_errors(const BatchMeansErrorEstimate& e);

  RegionGrid grid_;
  const Accumulator& pt_accum_;
  const Accumulator& rb_accum_;
  double pt_scale_, rb_scale_;  // 1 / samples per round
  std::vector<double> region_scales_;  // 1 / the region's pixels
  std::vector<double> pt_sums_, rb_sums_;
  RoundSums pt_round_sums_, rb_round_sums_;
  std::optional<BatchMeansErrorEstimate> pt_, rb_;
};

}  // namespace bp

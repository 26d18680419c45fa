// The image's regional error without a reference (docs/design.md §9, "Regional error"): per region of a
// grid (image/regions.h), the standard error of the region's mean luminance in the image as written.
//
// A pixel's standard error is not enough: RB's chain moves the light of whole rooms together, so
// its pixels' errors are correlated and a wall's mean is far more wrong than its pixels' variances
// summed as if independent say. So RB's region means are batched like the image's error estimate
// (image/error_estimate.h): a batch's region mean carries every correlation inside the region, and
// the variance of a region's mean is the spread of its batch means, with no assumption about how
// pixels correlate. RB's batches must outlast its chain's correlation between iterations
// (kRegionalBatchRbIterations: its lag-1 correlation of region means is measured in --stats). PT's
// pixels are independent (each its own random numbers, weights from patch-level inputs), so PT's
// share of a region's variance is its pixels' variances summed, Σ Var(Y_p) / n²: each pixel's from
// the same batches, but summed over thousands of pixels the region's variance is known far better
// than from the region's few batch means.
//
// What is tracked per region, as the mean luminance of a round's estimate: PT's weighted layer w,
// PT's unweighted estimate u, RB's weighted layer r, and PT's estimate of RB's share d = u − w.
// The image's region mean is
//   w + s·r                        RB's layer scaled by a factor s taken as exact (--rb-level own:
//                                  s = 1; corrected: one factor per channel), or
//   w + λ r + (1 − λ) d            --rb-level regional: RB's share in the region is the mean M of r
//                                  and d of least squared error, λ = V_d / (V_r + V_d + b²), where
//                                  b² = max(0, (r − d)² − V_r − V_d) estimates the square of RB's
//                                  discretisation bias in the region (d is unbiased; without a
//                                  bias, the inverse-variance mean),
// with variances V_w + s² V_r, or V_w + λ² (V_r + b²) + (1 − λ)² V_d + 2 (1 − λ) Cov(w, d), where
// Cov(w, d) = (V_u − V_w − V_d) / 2 since u = w + d (PT's layers share their samples).
// RbLevel's field takes its λ from here (rb_weights), but a smooth field cannot always give a region
// exactly its factor (the factors' limits; RB's layer concentrated where the neighbours' centres
// weigh): the region's mean as written is w + s·r with the field's effective s, and what it misses of
// the λ formula's mean, δ = (w + s·r) − (w + λ r + (1 − λ) d), is known and counted as error:
// the region's variance is that of the λ formula plus δ².
#pragma once
#include "image/accumulator.h"
#include "image/error_estimate.h"
#include "image/regions.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace bp {

// RB iterations per batch of the regional estimate, and the most a combined render's loop batch
// holds (passes/combined.cpp), so that a short render of few rounds still has batches to spread.
// Whether 16 iterations outlast RB's correlation is checked, not assumed: --stats reports the lag-1
// correlation of consecutive batches' region means (rb_batch_correlation), and the z-scores of
// bench/regional_error.sh and tests/e2e/test_regional_error.cpp test the variance it gives. On the
// Lambert house at 320x180, c = 1/2, 32 batches, seeds 1–4, it read 0.04 / 0.07 / −0.09 / 0.10 at
// 16 iterations, 0.08 / 0.07 / −0.06 / −0.02 at 8 and −0.12 / 0.00 / −0.07 / 0.05 at 32 (each ±0.1
// or so): no correlation to see. Shorter batches matter where a round has few iterations (c near
// 1): --target-block-error is checked from the second batch on (at c = 1/2 with 32-iteration
// batches the house's first check came at 32 rounds, its blocks then 1.25x under a 1 % target).
constexpr std::uint64_t kRegionalBatchRbIterations = 16;

// A region's variance of RB's mean from its own batches has batches − 1 degrees of freedom, and a
// short render at a small c holds few batches (the Phong house at 1280x720, 30 s: two rounds of 128
// iterations, one degree of freedom; one of its 64 regions reported 7 of its own standard errors off).
// So each region's relative variance of RB's mean, V_r / r², is pooled with that of all regions,
// Σ V_r / Σ r², counted as this many degrees of freedom of its own (the normal-inverse-χ² posterior
// mean): (ν V_r / r² + ν₀ q̄) / (ν + ν₀). The pool holds because RB's chain moves the light of every
// region alike: on the Lambert house (--mode rb, 320x180, 1024 iterations, 16 degrees of freedom)
// the regions' relative standard errors spread 0.046–0.146 (a coefficient of variation of 0.24,
// 0.18 of it the estimates' own), and the pooled q̄ is within 3 % of their mean and median; a true
// spread of ±17 % in the standard error makes the pool worth about 16 degrees of freedom of a
// region's own, and half of that is counted.
constexpr double kRegionalRbPoolDegreesOfFreedom = 8.0;

class RegionalError {
 public:
  struct Inputs {
    const Accumulator* pt = nullptr;  // PT's layer (its raw sums, where kept, give u and d)
    std::uint32_t pt_samples = 1;     // per round
    const Accumulator* rb = nullptr;  // RB's layer
    std::uint32_t rb_iterations = 1;  // per round
    std::uint64_t rb_batch_rounds = 1;
  };
  struct State {
    std::vector<BatchMeansErrorEstimate::State> layers;  // w, u, r, d: those that exist, in that order
  };
  // From round first_round (the accumulators hold rounds [0, first_round)), or a resumed state;
  // throws std::runtime_error if the state does not fit.
  RegionalError(RegionGrid grid, const Inputs& in, std::uint64_t first_round, const std::optional<State>& resumed);

  // After a batch of the render loop (the accumulators hold rounds [0, rounds)).
  void add(std::uint64_t rounds);
  // How RB's layer counts in the image: its per-pixel, per-channel factors (empty: 1), and whether
  // they are --rb-level regional's field on this grid (the λ formula above).
  void set_rb_factors(std::vector<double> pixel_factors, bool regional_field);
  // Per region, RB's weight λ in the inverse-variance mean of its share (the formula above), for
  // RbLevel's field; NaN where a variance is not known yet (fewer than two batches) or without d.
  std::vector<double> rb_weights() const;
  // Per region, the relative variance of RB's own level of its share, V_r / r², and of the level the
  // regional field gives it, Var(λ r + (1 − λ) d) / (λ r + (1 − λ) d)² with RB's bias counted (b²):
  // the image's per-pixel error under the field (ImageErrorEstimate::set_rb_regional_level). NaN
  // where not known.
  struct RbLevelVariances {
    std::vector<double> rb, corrected;
  };
  RbLevelVariances rb_level_relative_variances() const;

  const RegionGrid& grid() const { return grid_; }
  // Per region: the image's mean luminance as written, and its standard error (NaN until every
  // tracked layer has two batches).
  std::vector<double> region_means() const;
  std::vector<double> standard_errors() const;
  // Per region, the standard error over the mean (NaN where the mean is not positive).
  std::vector<double> relative_standard_errors() const;
  // The least degrees of freedom of a region's variance, over the regions and layers; 0 until every
  // layer has two batches. RB's pooled variance has ν + ν₀ (kRegionalRbPoolDegreesOfFreedom); PT's,
  // its pixels' variances summed, ν (Σ V_p)² / Σ V_p² (Welch–Satterthwaite: ν times the region's
  // pixels where they are alike, ν where one pixel holds all).
  double degrees_of_freedom() const;
  // Per region, the lag-1 correlation of RB's consecutive batch means (luminance), pooled over the
  // regions: the check that the batches outlast the chain's correlation (NaN: no RB, or < 3 batches).
  double rb_batch_correlation() const;
  State state() const;

 private:
  struct Track {
    bool per_pixel = false;    // PT's: per pixel; RB's: per region
    std::vector<double> sums;  // luminance over rounds, per pixel or region, packed three a value slot
    RoundSums round_sums;
    std::optional<BatchMeansErrorEstimate> estimate;
    std::vector<double> batch_means;  // RB's: every closed batch's region means, for the correlation
  };
  // The estimate's "image" that holds a track's luminances three to a pixel: width, height 1.
  int packed_width(const Track& t) const;
  void update_sums();
  std::vector<double> variances(const Track& t) const;
  std::vector<double> rb_variances() const;  // RB's, pooled (kRegionalRbPoolDegreesOfFreedom)
  std::vector<double> region_totals(const Track& t, const std::vector<double>& values, bool squared_scale) const;
  std::vector<double> means(const Track& t) const;
  std::vector<Track*> tracks();
  std::vector<const Track*> tracks() const;

  RegionGrid grid_;
  Inputs in_;
  std::vector<double> inv_pixels_;     // per region, 1 / its pixels
  std::optional<Track> w_, u_, r_, d_;
  std::vector<double> rb_factors_;     // per region, the effective factor s on RB's mean luminance
  bool regional_field_ = false;
  std::uint64_t rb_batches_seen_ = 0;
};

// The expected largest of |e_b| over regions whose errors e_b are independent normals with these
// standard deviations (NaN entries skipped): what "the worst block is off by" is expected to read.
// E[max] = ∫₀^∞ (1 − Π_b erf(t / (σ_b √2))) dt.
double expected_largest_error(const std::vector<double>& standard_deviations);

}  // namespace bp

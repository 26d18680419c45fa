// The image's error without a reference (docs/design.md §9): batch means. The render's rounds are grouped
// into batches of at least `batch_rounds` rounds (closed at the render loop's batch ends); each
// batch's mean image is an independent estimate of the pixel when the batches outlast the estimator's
// correlation (PT: one round; RB: a Markov chain, kErrorBatchRbIterations), so their spread gives the
// variance of the image's mean per pixel, and from it the relMSE the image is expected to have.
// Memory: two doubles per pixel and channel per level (the open batch's start and the sum of squares).
#pragma once
#include "image/image.h"
#include "image/regions.h"
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bp {

// RB iterations per batch: the chain's correlation must end well inside a batch. Measured with
// bench/error_estimate.sh's blocking study (README, "Error estimates"): the estimate of 64-iteration
// batches equals that of 128 to 512 within its noise on cornell-box, cornell-glossy and the house
// (the lag-1 correlation of consecutive 64-iteration batch means is a few percent), while the eye
// hits are re-jittered every 16 iterations, so a batch must hold whole blocks of 16 anyway.
constexpr std::uint64_t kErrorBatchRbIterations = 64;
// A render expected to hold fewer than this many such batches gets shorter ones, whole blocks of the
// eye hits' 16, so that a short one at a large c still has an estimate (a glossy house at c = 1/2 in
// 30 s: 80 iterations, one batch of 64). Few: the rb_bias check (kRbBiasMinPairedBatches) is not
// started sooner by it.
constexpr std::uint64_t kErrorBatchesWanted = 4;
constexpr std::uint64_t kErrorBatchRbBlock = 16;
// RB's batch for a render expected to run this many iterations (not finite: unknown).
std::uint64_t rb_error_batch_iterations(double expected_iterations);

// rb_bias_rel_mse counts RB's bias where its estimate is above this one-sided Student-t quantile
// (a 5 % false alarm, student_t_95 in error_estimate.cpp) times its standard error, and only once
// kRbBiasMinPairedBatches of RB's batches have paired with earlier ones: the standard error is the
// spread of a few increments of unequal variance, and from fewer it is too often far too small. Both
// come from RB's batches, so they see the chain's noise however far it spreads over the image. Before,
// the standard error came from the pixels' spread, as if their errors were independent: RB's chain
// moves whole rooms' light together, and on the 8spp + 256it Lambert house the check counted 0.0012
// of "bias" on three seeds of eight (the estimate 3x the measured); with the batches' standard error
// but from three increments (four batches), still on one seed of eight (its standard error 7e-5).
// On cornell-glossy at 8spp + 1024it (seven increments) RB's discretisation reads 0.0018-0.0028 at
// 2.9-5 standard errors: a 1 % false alarm (t 3.14) missed the 2.9 and left that render's estimate
// at 0.44x its measured error. A missed bias under-reports; a false alarm over-reports by about RB's
// own variance: the 5 % errs on the side of reporting.
constexpr double kRbBiasFalseAlarm = 0.05;
constexpr std::uint64_t kRbBiasMinPairedBatches = 5;
// --target-error stops only once the estimate has this many degrees of freedom (eight batches of one
// layer): the variance of fewer is too uncertain for a lucky low estimate to be unlikely.
constexpr double kMinDegreesOfFreedomForTarget = 7.0;

// A weighted sum of per-pixel doubles (an accumulator's sums over rounds) that makes one estimator's
// layer times the rounds: the combined image is pt.sum / N1 + rb.sum / N2 per round (eq. 3).
struct RoundSums {
  const std::vector<double>* sums = nullptr;
  double scale = 1.0;
  const std::vector<double>* minus = nullptr;  // subtracted before scaling (PT's unweighted less weighted sums)
  double at(std::size_t i) const { return ((*sums)[i] - (minus ? (*minus)[i] : 0.0)) * scale; }
};

class BatchMeansErrorEstimate {
 public:
  // One level per batch length batch_rounds · 2^j, j < levels (level 0 is the estimate; the others
  // are the blocking check that the batches outlast the correlation). Starts at round `first_round`
  // with the sums `start` (what a resumed render had before; null: zero).
  BatchMeansErrorEstimate(int width, int height, std::uint64_t batch_rounds, int levels = 1,
                          std::uint64_t first_round = 0, const RoundSums* start = nullptr);

  // After a batch of the render loop: the sums over rounds [0, rounds) of each pixel's estimate.
  void add(std::uint64_t rounds, const RoundSums& sums);

  std::uint64_t batch_rounds(int level = 0) const { return state_.levels[std::size_t(level)].batch_rounds; }
  std::uint64_t batches(int level = 0) const { return state_.levels[std::size_t(level)].batches; }
  int levels() const { return int(state_.levels.size()); }
  std::uint64_t rounds() const { return state_.rounds; }
  // Per pixel and channel, the variance of the image's mean over `rounds()` rounds: the batch means'
  // variance s² = Σ n_k (m_k − m)² / (K − 1) (n_k rounds in batch k, unbiased for unequal batches),
  // over the rounds, s² / N. Empty with fewer than two batches.
  std::vector<double> variance_of_mean(int level = 0) const;
  // docs/design.md §7's relMSE with that variance in place of (I − R)² and, in place of R, the smaller of
  // the pixel and the mean of its 8 neighbours in the image (error_estimate.cpp says why not the
  // pixel alone): mean(Var / (R̂² + 0.01)). NaN with fewer than two batches.
  double estimated_rel_mse(const ImageRGB& image, int level = 0) const;
  // The same with the image of the sums given to the last add(), I = sums / rounds().
  double estimated_rel_mse(const RoundSums& sums, int level = 0) const;

  // What a checkpoint keeps (passes/checkpoint.cpp).
  struct Level {
    std::uint64_t batch_rounds = 0;       // at least this many rounds per batch
    std::uint64_t batches = 0;            // closed batches K
    std::uint64_t closed_rounds = 0;      // rounds in them, Σ n_k
    std::uint64_t open_round = 0;         // where the open batch started
    std::vector<double> open_sums;        // the sums at that round
    std::vector<double> sum_sq_over_n;    // Σ X_k² / n_k, X_k = a batch's sum over its rounds
  };
  struct State {
    int width = 0, height = 0;
    std::uint64_t rounds = 0;
    std::vector<double> start_sums;       // at the first round (empty: zero)
    std::vector<Level> levels;
  };
  const State& state() const { return state_; }
  // Throws std::runtime_error if it does not fit an image of width x height.
  static BatchMeansErrorEstimate from_state(State state, int width, int height);

 private:
  BatchMeansErrorEstimate() = default;
  State state_;
};

// The image's error from the independent estimators whose layers sum to it (docs/design.md §9): the
// combination's PT and RB layers draw their own random numbers and weigh with patch-level inputs
// alone, so the variance of the image is the sum of the layers' variances, each from batches of its
// own length -- PT's of one round (its rounds are independent), RB's of kErrorBatchRbIterations (a
// chain). So PT's share has its degrees of freedom after a few rounds while RB's batches are long,
// and --target-error waits for the degrees of freedom of the sum (Welch–Satterthwaite), not for
// eight of RB's long batches. --rb-level scales RB's layer in the image by a factor per pixel and
// channel (image/rb_level.h): its variance counts scaled by the factor's square, the factor taken as
// exact (its noise, and the correlation it brings between the layers, are of second order per pixel;
// over a region they are not, and image/regional_error.h counts them).
class ImageErrorEstimate {
 public:
  struct Layer {
    const char* name;                 // "pt", "rb": the image layer's name (render_outputs.h)
    RoundSums sums;                   // the layer times the rounds
    std::uint64_t batch_rounds = 1;   // its batches' least length
  };
  // `levels` batch lengths per layer (the blocking check, BatchMeansErrorEstimate). Starts at round
  // `first_round` (the layers' sums then are where its batches start), or from a checkpoint's
  // `resumed` states, one per layer and then the check's; throws std::runtime_error if they do not fit.
  // `pt_rb_share`, where given (a combined render), is PT's estimate of RB's share times the rounds,
  // d = u − w per round (its unweighted less its weighted sums), batched with RB's layer: the check
  // of RB's layer against it (rb_bias_rel_mse).
  ImageErrorEstimate(int width, int height, std::vector<Layer> layers, int levels, std::uint64_t first_round,
                     const std::vector<BatchMeansErrorEstimate::State>* resumed = nullptr,
                     std::optional<RoundSums> pt_rb_share = std::nullopt);

  // After a batch of the render loop: the layers' sums hold rounds [0, rounds).
  void add(std::uint64_t rounds);
  // The factor per pixel and channel (interleaved RGB) with which the layer named so counts in the
  // image (1 unless set; --rb-level's field, image/rb_level.h).
  void set_factors(const std::string& layer, std::vector<double> factors);

  // --rb-level regional (image/rb_level.h): RB's layer counts in the image with each region's level
  // replaced by the corrected level, so of RB's per-pixel variance only what varies within the region
  // stays, and the corrected level's own variance comes instead. Per region of `grid`, ρ_r: the
  // relative variance of RB's level, Var(r̄) / r̄²; ρ_M: the corrected level's (image/regional_error.h).
  // Per value, Var(s·r) = s² max(0, Var(r) − r² ρ_r) + (s·r)² ρ_M: the level's fluctuation taken as
  // common to the region's pixels in proportion to each (a multiplicative level, as RB's chain moves
  // whole rooms' light). Without it (the 8spp + 256it house) RB's per-pixel variances counted the
  // level the regional field had replaced: the estimate was 2-3x the spread between seeds.
  void set_rb_regional_level(const RegionGrid& grid, std::vector<double> rb_level_relative_variance,
                             std::vector<double> corrected_level_relative_variance);
  // --rb-level consistent (image/share_correction.h): the image is PT's weighted layer plus RB's share
  // corrected by PT's estimate of it, so its error per pixel and channel is not the layers' sum; the
  // caller gives it (`mean_square_error`: PT's part's variance plus what the correction left of RB's,
  // bias included) with the image. Level 0's variance and the standard error are then these, and no
  // separate term for RB's bias is added or waited for. Empty: the layers' sum again.
  void set_consistent_share(std::vector<double> mean_square_error, std::vector<float> image);
  // The image's relMSE (BatchMeansErrorEstimate's formula) with the layers' variances summed, from
  // each layer's batches of level j, plus rb_bias_rel_mse where it is known; NaN until every layer has
  // two batches.
  double estimated_rel_mse(int level = 0) const;
  // What RB's layer as it counts in the image (s·r per pixel) is off from PT's unbiased estimate of
  // the same share (d) beyond both noises: RB's discretisation (patches, their Gouraud interpolation,
  // glossy lobes over a patch), which no variance sees. From RB's batches k (n_k rounds; the check's
  // d batched alike), y_k = s·r_k − d_k summed over the batch: E[y_k y_l] = n_k n_l b² for k ≠ l (the
  // batches independent), so the pairs' products, each over the image as the relMSE sums (rb_bias_check),
  // estimate the relMSE of the bias b without a noise term to subtract. Counted where significant
  // (kRbBiasFalseAlarm), else 0; NaN without the check or before kRbBiasMinPairedBatches.
  double rb_bias_rel_mse() const;
  // A combined render whose check has not counted yet (fewer than kRbBiasMinPairedBatches paired
  // batches): its estimate has no term for RB's bias so far, and --target-error waits for one.
  bool rb_bias_pending() const {
    return pt_rb_share_estimate_.has_value() && std::isnan(rb_bias_rel_mse()) && consistent_mse_.empty();
  }
  // The round by which the check will have paired kRbBiasMinPairedBatches batches (RB's open batch
  // and the batches still missing, each of RB's batch length); 0 without the check.
  std::uint64_t rb_bias_rounds_needed() const;
  struct RbBiasCheck {
    double estimate = NAN;        // Σ_k E_k / Σ_k a_k, E_k = mean over values of y_k·Y_<k / (R̂² + 0.01), a_k = n_k N_<k
    double standard_error = NAN;  // from the spread of E_k about a_k·estimate (a martingale's increments)
    std::uint64_t batches = 0;    // closed batches that paired with earlier ones
  };
  RbBiasCheck rb_bias_check() const;
  // The check's sums over RB's closed batches (rb_bias_check): what a checkpoint keeps of it.
  struct RbBiasSums {
    double e = 0.0, e_sq = 0.0, a = 0.0, a_e = 0.0, a_sq = 0.0;
    std::uint64_t batches = 0;
  };
  const RbBiasSums& rb_bias_sums() const { return rb_bias_sums_; }
  void resume_rb_bias_sums(const RbBiasSums& sums) { rb_bias_sums_ = sums; }
  // Each layer's share of it: its variance over the image's reference values (NaN: fewer than two batches).
  double layer_rel_mse(std::size_t layer, int level = 0) const;
  // The degrees of freedom of estimated_rel_mse(): Welch–Satterthwaite's (Σ V_l)² / Σ (V_l² / (K_l − 1)),
  // V_l a layer's relMSE from K_l batches, each layer's variance counted as one chi-square of K_l − 1
  // (RB's error is the same sign over the image, so its pixels add no freedom; PT's would add some,
  // so this is its least); 0 until every layer has two batches. One layer: K − 1.
  double degrees_of_freedom() const;
  // The standard error of each pixel of the image, sqrt(Σ Var_l) (zeros until every layer has two batches).
  ImageRGB standard_error() const;

  const std::vector<BatchMeansErrorEstimate>& layers() const { return estimates_; }
  const char* layer_name(std::size_t layer) const { return layers_[layer].name; }
  std::vector<BatchMeansErrorEstimate::State> state() const;

 private:
  std::vector<double> layer_variance(std::size_t layer, int level) const;  // as it counts; empty: not yet
  std::vector<double> variance_of_mean(int level) const;  // summed over the layers; empty: not yet
  double rel_mse_of(const std::vector<double>& variance) const;
  int width_, height_;
  std::vector<Layer> layers_;
  std::vector<std::vector<double>> factors_;  // per layer, per value; empty: 1
  double factor(std::size_t layer, std::size_t i) const { return factors_[layer].empty() ? 1.0 : factors_[layer][i]; }
  std::vector<BatchMeansErrorEstimate> estimates_;
  std::optional<RoundSums> pt_rb_share_;
  std::optional<RegionGrid> rb_level_grid_;  // set_rb_regional_level's
  std::vector<double> rb_level_rho_r_, rb_level_rho_m_;
  std::vector<double> consistent_mse_;  // set_consistent_share's
  std::vector<float> consistent_image_;
  std::optional<BatchMeansErrorEstimate> pt_rb_share_estimate_;  // d, batched with RB's layer
  RbBiasSums rb_bias_sums_;
  std::size_t rb_layer() const;  // layers_.size(): none
  void add_rb_bias_batch(std::size_t rb, std::uint64_t rounds);
};

}  // namespace bp

// The image's error without a reference (DESIGN.md §9): batch means. The render's rounds are grouped
// into batches of at least `batch_rounds` rounds (closed at the render loop's batch ends); each
// batch's mean image is an independent estimate of the pixel when the batches outlast the estimator's
// correlation (PT: one round; RB: a Markov chain, kErrorBatchRbIterations), so their spread gives the
// variance of the image's mean per pixel, and from it the relMSE the image is expected to have.
// Memory: two doubles per pixel and channel per level (the open batch's start and the sum of squares).
#pragma once
#include "image/image.h"
#include <cstdint>
#include <vector>

namespace bp {

// RB iterations per batch: the chain's correlation must end well inside a batch. Measured with
// bench/error_estimate.sh's blocking study (README, "Error estimates"): the estimate of 64-iteration
// batches equals that of 128 to 512 within its noise on cornell-box, cornell-glossy and the house
// (the lag-1 correlation of consecutive 64-iteration batch means is a few percent), while the eye
// hits are re-jittered every 16 iterations, so a batch must hold whole blocks of 16 anyway.
constexpr std::uint64_t kErrorBatchRbIterations = 64;

// --target-error stops only once this many batches are closed: the per-pixel variance of fewer has
// too few degrees of freedom for a lucky low estimate to be unlikely.
constexpr std::uint64_t kMinBatchesForTarget = 8;

// One or two weighted sums of per-pixel doubles (an accumulator's sums over rounds) that make the
// image times the rounds: the combined image is pt.sum / N1 + rb.sum / N2 per round (eq. 3).
struct RoundSums {
  const std::vector<double>* first = nullptr;
  double first_scale = 1.0;
  const std::vector<double>* second = nullptr;
  double second_scale = 1.0;
  double at(std::size_t i) const {
    return (first ? (*first)[i] * first_scale : 0.0) + (second ? (*second)[i] * second_scale : 0.0);
  }
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
  // DESIGN.md §7's relMSE with that variance in place of (I − R)² and, in place of R, the smaller of
  // the pixel and the mean of its 8 neighbours in the image (error_estimate.cpp says why not the
  // pixel alone): mean(Var / (R̂² + 0.01)). NaN with fewer than two batches.
  double estimated_rel_mse(const ImageRGB& image, int level = 0) const;
  // The same with the image of the sums given to the last add(), I = sums / rounds().
  double estimated_rel_mse(const RoundSums& sums, int level = 0) const;
  // The standard error of each pixel of the image, sqrt(Var) (zeros with fewer than two batches).
  ImageRGB standard_error(int level = 0) const;

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

}  // namespace bp

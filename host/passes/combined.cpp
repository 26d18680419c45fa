#include "passes/combined.h"

#include "image/regional_error.h"

#include <algorithm>
#include <chrono>
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
  if (shape.pt_alone()) return CombinedWeights{BP_WEIGHTS_NONE, 0.0f};
  return CombinedWeights{mode, float(1.0 / shape.ratio())};
}

// A round of N1 PT samples and N2 RB iterations takes N1 t_PT + N2 t_RB; PT's share of it is
//   f = N1 t_PT / (N1 t_PT + N2 t_RB)   <=>   c = N1 / N2 = f / (1 - f) · t_RB / t_PT.
// A fixed f rather than a fixed c follows the cost that moves with the scene and the resolution: PT's
// cost per sample grows with the pixels, an RB iteration's mostly with the patches (docs/design.md §3).
// c is snapped to a power of 2 (log-nearest): timing noise of a few percent rarely changes the
// choice, and an integer or its inverse is what round_shape makes a round of. It is clamped to
// [1/1024, 64]: past that a round (the unit a --time budget stops at) grows long for a pass that
// gets little of the time anyway.
double auto_ratio_pt_time_share(bool eye_direct_pt_alone) {
  return eye_direct_pt_alone ? kAutoRatioPtTimeShareEyePt : kAutoRatioPtTimeShareEyeShared;
}

RoundShape auto_ratio_shape(double pt_seconds_per_spp, double rb_seconds_per_iteration, double pt_time_share,
                            const AutoRatioBounds& bounds) {
  const double t_pt = std::max(pt_seconds_per_spp, 1e-9), t_rb = std::max(rb_seconds_per_iteration, 1e-9);
  if (t_rb > t_pt && bounds.pt_alone_allowed) return RoundShape{1, 0};
  const double f = t_rb > t_pt ? std::max(pt_time_share, kAutoRatioPtTimeShareRbCostly) : pt_time_share;
  const double c = f / (1.0 - f) * t_rb / t_pt;
  const int log2_c = std::clamp(int(std::lround(std::log2(c))), -10, 6);
  RoundShape shape = round_shape(std::ldexp(1.0, log2_c));
  // A round is N1 t_PT + N2 t_RB; one that does not fit the --time is halved (N2 first: the larger).
  const auto round_seconds = [&] { return shape.pt_samples * t_pt + shape.rb_iterations * t_rb; };
  while (bounds.round_seconds > 0.0 && round_seconds() > bounds.round_seconds &&
         (shape.rb_iterations > 1 || shape.pt_samples > 1)) {
    if (shape.rb_iterations > 1) shape.rb_iterations /= 2;
    else shape.pt_samples /= 2;
  }
  return shape;
}

double expected_pt_spp(const RoundShape& shape, std::uint64_t spp, std::uint64_t iterations, double seconds,
                       double pt_seconds_per_spp, double rb_seconds_per_iteration) {
  const double c = shape.ratio();
  double expected = 1e300;
  if (spp) expected = std::min(expected, double(spp));
  if (shape.pt_alone()) {  // PT alone: every second is PT's
    if (seconds > 0.0 && pt_seconds_per_spp > 0.0) expected = std::min(expected, seconds / pt_seconds_per_spp);
    return expected == 1e300 ? 64.0 : expected;
  }
  if (iterations) expected = std::min(expected, double(iterations) * c);
  // A second holds N1 t_PT + N2 t_RB per round of N1 = c N2: c / (c t_PT + t_RB) samples per pixel.
  if (seconds > 0.0 && pt_seconds_per_spp + rb_seconds_per_iteration > 0.0)
    expected = std::min(expected, seconds * c / (c * pt_seconds_per_spp + rb_seconds_per_iteration));
  return expected == 1e300 ? 64.0 : expected;  // no budget: the combined default of 64 spp
}

std::uint64_t equal_time_rounds(std::uint64_t equal_time_spp, const RoundShape& shape, double pt_seconds_per_spp,
                                double rb_seconds_per_iteration) {
  const double round_seconds = shape.pt_samples * pt_seconds_per_spp + shape.rb_iterations * rb_seconds_per_iteration;
  if (!(pt_seconds_per_spp > 0.0) || !(round_seconds > 0.0))
    return std::max<std::uint64_t>(1, (equal_time_spp + shape.pt_samples - 1) / std::max<std::uint32_t>(1, shape.pt_samples));
  return std::max<std::uint64_t>(1, std::uint64_t(std::llround(double(equal_time_spp) * pt_seconds_per_spp / round_seconds)));
}

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Runs `step(first, count)` in batches that double (capped at max_batch) until `seconds` of timed
// work are done (at least one step), adding the time and the count to *timed_seconds / *timed_count.
// With min_steps: at least that many steps (and samples), none of more than 1 / min_steps of what fits.
template <class Step>
void time_until(double seconds, std::uint32_t max_batch, std::uint64_t first, Step step, double* timed_seconds,
                std::uint64_t* timed_count, int min_steps = 1) {
  std::uint32_t batch = 1;
  const std::uint64_t count_before = *timed_count;
  for (;;) {
    const auto t = std::chrono::steady_clock::now();
    step(first + *timed_count, batch);
    *timed_seconds += seconds_since(t);
    *timed_count += batch;
    const double per = *timed_seconds / double(*timed_count);
    const double fits = std::max(seconds / per, double(count_before + std::uint64_t(min_steps)));  // in all
    const double left = fits - double(*timed_count);  // what still fits, in steps
    if (left < 1.0) break;
    const double spread = std::floor((fits - double(count_before)) / double(min_steps));  // min_steps fit
    batch = std::uint32_t(std::clamp<double>(std::min({2.0 * batch, std::ceil(left), spread}), 1.0, double(max_batch)));
  }
}
}  // namespace

ProbeImageSize probe_image_size(int width, int height) {
  const double pixels = double(width) * height;
  if (pixels <= double(kAutoRatioProbePixels)) return ProbeImageSize{width, height};
  const double scale = std::sqrt(double(kAutoRatioProbePixels) / pixels);
  return ProbeImageSize{std::max(1, int(std::lround(width * scale))), std::max(1, int(std::lround(height * scale)))};
}

double gloss_pt_time_share(double pt_variance_kept) {
  if (!(pt_variance_kept > 0.0)) return 0.0;
  const double a = std::sqrt(std::min(pt_variance_kept, 1.0));
  return a / (a + std::sqrt(kAutoRatioRbVarianceOverPt));
}

double probed_pt_time_share(double base_share, double pt_variance_kept) {
  return std::max(base_share, gloss_pt_time_share(pt_variance_kept));
}

RatioProbe probe_ratio(PathTracerPass& probe_pt, const Accumulator& probe_pt_accum, std::size_t pixels,
                       RayBundlePass& rb, const std::vector<Accumulator*>& rb_accums, const RatioProbeBudget& budget) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Accumulator> rb_before;
  for (const Accumulator* a : rb_accums) rb_before.push_back(*a);
  const RayBundlePass::State rb_before_state = rb.save_state();
  // The probe times RB iterations with their eye estimate, not the warm-up: marked as warmed up.
  rb.load_state(RayBundlePass::State{rb_before_state.e_in, 0, true});
  // Untimed: the first launch of each kernel builds its work-group code on some devices (PoCL, seconds
  // on a cold cache). PT's is a launch of 0 samples per pixel (no path traced); RB's a whole iteration.
  probe_pt.run(0, 0);
  rb.run(0, 1);
  const double first_launch_seconds = seconds_since(start);
  double pt_seconds = 0.0, rb_seconds = 0.0;
  std::uint64_t pt_count = 0, rb_count = 0;
  const auto rb_step = [&](std::uint64_t f, std::uint32_t n) { rb.run(f, n); };
  time_until(0.0, 1, 0, [&](std::uint64_t f, std::uint32_t n) { probe_pt.run(f, n); }, &pt_seconds, &pt_count);
  time_until(0.0, 1, 1, rb_step, &rb_seconds, &rb_count);
  const double pt_scale = double(pixels) / (double(probe_pt.pixel_width()) * probe_pt.pixel_height());
  // The probe's size: a share of the render's time, estimated from these two when only a count is given.
  // No budget: the render takes what equal_time_spp PT samples would, and its round must fit that.
  const double seconds =
      budget.seconds > 0.0 ? budget.seconds : double(budget.equal_time_spp) * pt_seconds / double(pt_count) * pt_scale;
  const AutoRatioBounds bounds{seconds, budget.iterations == 0};
  const RoundShape first_guess = auto_ratio_shape(pt_seconds * pt_scale, rb_seconds, budget.pt_time_share, bounds);
  double render_seconds = seconds > 0.0 ? seconds : 1e30;
  if (budget.spp || budget.iterations) {
    const double rounds = budget.spp ? std::ceil(double(budget.spp) / first_guess.pt_samples)
                                     : std::ceil(double(budget.iterations) / first_guess.rb_iterations);
    render_seconds = std::min(render_seconds, rounds * (first_guess.pt_samples * pt_seconds * pt_scale +
                                                        first_guess.rb_iterations * rb_seconds));
  }
  const double probe_seconds = std::min(kAutoRatioProbeCapSeconds, kAutoRatioProbeShare * render_seconds);

  // PT's remaining probe samples under the weights of the costs' round, each launch a batch of the
  // variance of its weighted and of its unweighted samples (from where the weights were set).
  if (!first_guess.pt_alone()) {
    const CombinedWeights weights = combined_weights(budget.weight_mode, first_guess);
    probe_pt.set_weights(weights.mode, weights.ratio_n2_over_n1);
  }
  const int width = int(probe_pt.pixel_width()), height = int(probe_pt.pixel_height());
  const std::vector<double> weighted_start = probe_pt_accum.sum, raw_start = probe_pt_accum.raw_sum;
  const std::uint64_t variance_first = pt_count;
  BatchMeansErrorEstimate weighted_variance(width, height, 1), raw_variance(width, height, 1);
  const RoundSums weighted_sums{&probe_pt_accum.sum, 1.0, &weighted_start};
  const RoundSums raw_sums{&probe_pt_accum.raw_sum, 1.0, &raw_start};
  const auto pt_step = [&](std::uint64_t f, std::uint32_t n) {
    probe_pt.run(f, n);
    if (!probe_pt_accum.keeps_raw()) return;
    weighted_variance.add(f + n - variance_first, weighted_sums);
    raw_variance.add(f + n - variance_first, raw_sums);
  };
  // Enough batches for κ where they cost at most kAutoRatioProbeVarianceShare of the render.
  const bool variance_affordable = kAutoRatioProbeMinPtBatches * pt_seconds / double(pt_count) <=
                                   kAutoRatioProbeVarianceShare * render_seconds;
  time_until(probe_seconds / 2, probe_pt.max_batch(), 0, pt_step, &pt_seconds, &pt_count,
             variance_affordable ? kAutoRatioProbeMinPtBatches : 1);
  time_until(probe_seconds / 2, rb.max_batch(), 1, rb_step, &rb_seconds, &rb_count);
  for (std::size_t k = 0; k < rb_accums.size(); ++k) *rb_accums[k] = rb_before[k];
  rb.load_state(rb_before_state);

  RatioProbe probe;
  probe.pt_seconds_per_spp = pt_seconds / double(pt_count) * pt_scale;
  probe.rb_seconds_per_iteration = rb_seconds / double(rb_count);
  probe.pt_samples = std::uint32_t(pt_count);
  probe.rb_iterations = std::uint32_t(rb_count);
  probe.pt_image = ProbeImageSize{width, height};
  probe.pt_variance_batches = raw_variance.batches();
  if (raw_variance.batches() >= std::uint64_t(kAutoRatioProbeMinPtBatches) && !first_guess.pt_alone()) {
    // Both relMSEs against the unweighted samples' mean image (the same rounds): the same pixels' scale.
    const double raw_rel_mse = raw_variance.estimated_rel_mse(raw_sums);
    if (raw_rel_mse > 0.0) probe.pt_variance_kept = weighted_variance.estimated_rel_mse(raw_sums) / raw_rel_mse;
  }
  probe.pt_time_share = probed_pt_time_share(budget.pt_time_share, probe.pt_variance_kept);
  probe.bounds = bounds;
  probe.chosen =
      auto_ratio_shape(probe.pt_seconds_per_spp, probe.rb_seconds_per_iteration, probe.pt_time_share, bounds);
  probe.probe_seconds = seconds_since(start);
  probe.first_launch_seconds = first_launch_seconds;
  return probe;
}

BatchCounts CombinedPass::run(std::uint64_t first, std::uint32_t count) {
  BatchCounts total;
  const std::uint64_t pt_max = std::max<std::uint32_t>(1, pt_.max_batch());
  const std::uint64_t pt_end = (first + count) * shape_.pt_samples;
  for (std::uint64_t s = first * shape_.pt_samples; s < pt_end;) {
    const std::uint64_t next = std::min(pt_end, (s / pt_max + 1) * pt_max);
    total += pt_.run(s, std::uint32_t(next - s));
    s = next;
  }
  if (!shape_.pt_alone()) total += rb_.run(first * shape_.rb_iterations, count * shape_.rb_iterations);
  return total;
}

std::uint32_t CombinedPass::max_batch() const {
  if (shape_.pt_alone()) return std::max<std::uint32_t>(1, pt_.max_batch() / shape_.pt_samples);
  if (shape_.pt_samples == 0) return std::max<std::uint32_t>(1, rb_.max_batch() / shape_.rb_iterations);  // as --mode rb
  // With PT, a loop batch holds at most kRegionalBatchRbIterations of RB (or one round): the
  // regional error's batches (image/regional_error.h) close at loop batch ends, and a short render
  // needs several.
  const std::uint32_t rb =
      std::min<std::uint32_t>(rb_.max_batch(), std::uint32_t(kRegionalBatchRbIterations)) / shape_.rb_iterations;
  return std::max<std::uint32_t>(1, std::min(pt_.max_batch() / shape_.pt_samples, rb));
}

}  // namespace bp

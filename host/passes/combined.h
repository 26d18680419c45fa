// The weighted multipass combination (docs/design.md §1): rounds of PT samples and RB iterations at a fixed
// ratio c = N1 / N2, so the weights stay right whenever the render stops at a round's end. The
// combined image is pt + rb of the two weighted accumulators (eq. 3).
#pragma once
#include "passes/path_tracer.h"
#include "passes/ray_bundles.h"
#include <cmath>

namespace bp {

// One round: pt_samples samples per pixel and rb_iterations iterations; c = pt_samples / rb_iterations.
// pt_samples = 0 (c = 0) is ray bundles alone; rb_iterations = 0 (c = ∞) the path tracer alone, which
// only --ratio auto chooses (auto_ratio_shape).
struct RoundShape {
  std::uint32_t pt_samples = 1;
  std::uint32_t rb_iterations = 1;
  double ratio() const { return rb_iterations ? double(pt_samples) / double(rb_iterations) : INFINITY; }  // c = N1 / N2
  bool pt_alone() const { return rb_iterations == 0; }
};

// The smallest integer round whose ratio is c (within 1 %): c >= 1 gives (round(c), 1), c < 1 gives
// (1, round(1/c)), c = 0 gives (0, 1). Throws std::invalid_argument naming --ratio for c outside
// {0} ∪ [1e-6, 1e6] or not finite.
RoundShape round_shape(double c);

// The weight mode and N2 / N1 that both passes get for `mode` (BP_WEIGHTS_*) at this round shape.
// With no PT samples (c = 0) every weight is trivially w_RB = 1 (product: β = N2 / (N2 + 0·…) = 1;
// paper: N2 / (0·P* + N2) = 1), so RB runs unweighted (BP_WEIGHTS_NONE): passing N2 / N1 = ∞ to the
// kernels would make β = ∞ / (∞ + p) a NaN. With no RB iterations (c = ∞) every weight is w_PT = 1:
// PT runs unweighted, as --mode pt.
struct CombinedWeights {
  std::uint32_t mode = BP_WEIGHTS_NONE;
  float ratio_n2_over_n1 = 1.0f;
};
CombinedWeights combined_weights(std::uint32_t mode, const RoundShape& shape);

// --ratio auto (docs/design.md §3, "The ratio c"): the share of the render time PT gets. It depends on who
// estimates the eye vertex's direct light. Where it is PT's alone (--eye-direct pt, chosen by auto at
// many PT samples per pixel) PT's variance holds a part RB cannot take, and the split that minimises
// A / f + B / (1 - f) (A, B: the PT and RB parts' variance at equal time) is f = √A / (√A + √B):
// measured on cornell-glossy at 128x128 (README, issue #12; equal-work runs, 4 seeds) A : B ≈ 3.2 : 1,
// so f ≈ 0.64, and at 20 s c = 1/2 (0.65) gave 0.00035 / 0.00037 against 0.00037 / 0.00041 at c = 1/4
// (0.5). Where it is shared (few PT samples per pixel: real resolutions, short budgets) RB carries
// most of the image, and since --rb-level corrected PT's samples are needed mostly for RB's level,
// which a few samples per pixel of a whole image estimate well. In the sweep (bench/results/sweep/,
// README "The sweep") the houses at 640x360 share it and are best at c = 1/64, a PT share of 0.06;
// 0.12 picks 1/32 there, at 0.91x the best's efficiency (1/16 at 0.83-0.85x), leaving room for scenes
// less RB-friendly than a Lambert house (a first try with 256-spp references put the boxes at
// 0.15-0.19; with 1024-spp ones they take the light PT's alone at 640x360). `render --help`
// (cli/options.cpp) quotes these constants.
constexpr double kAutoRatioPtTimeShareEyeShared = 0.12;
constexpr double kAutoRatioPtTimeShareEyePt = 0.65;
// Where one RB iteration costs more than a PT sample of the whole image (t_RB > t_PT: many more
// patches than pixels, e.g. the 122 000-patch house at 128x128, t_RB/t_PT ≈ 2), RB's transport over
// every patch buys an image of few pixels, and PT gets at least this share. Measured there at 16 s
// (bench/results/sweep/, README "The sweep"): c = 64 best, 16 at 0.94 of it, 4 at 0.70; four seeds
// each on a second machine (bench/results/house-128-repeats.md): c = 32 does 320 spp where PT alone
// does 384 and is 1.19x its relMSE, c = 64 ties it at equal spp. RB's few iterations add nothing
// there, and its cost is what the ratio can shrink: where it may, auto chooses PT alone (c = ∞) wherever
// t_RB > t_PT; where the render counts RB iterations (--iterations) it may not, and 0.98 picks 64 (the
// largest finite c). Nowhere else in the sweep is t_RB > t_PT (0.04 to 0.26).
constexpr double kAutoRatioPtTimeShareRbCostly = 0.98;
// The share for a render whose eye vertex's direct light is PT's alone (or not).
double auto_ratio_pt_time_share(bool eye_direct_pt_alone);
// Glossy scenes: the product weights leave PT the paths through sharp lobes at any c, so where much
// of the image is seen through them RB's time buys little of it. The probe measures κ, the share of
// PT's variance its weights keep: the relMSE of its weighted samples over that of the same samples
// unweighted, at the costs' round. Model: the image's relMSE at PT time share f is
// κ R_PT / f + β R_PT / (1 − f), R_PT the path tracer's alone at the same time, β the rest (RB's
// part) in its units; its least is at f = √κ / (√κ + √β), and PT gets at least that.
// β from fixed-c sweeps of the GGX house with its glossy materials at one roughness (640x360, 30 s,
// seeds 1–2, bench/results/ggx-roughness/): at roughness 0.05 (κ ≈ 0.33) c = 1/2 was best (relMSE
// 0.020–0.021 against 0.026 at 1/4, 0.023–0.025 at 1, PT's 0.023), at 0.15 (κ ≈ 0.19) c = 1/4 to 1/2
// (0.010–0.013 against 0.015 at 1/8, PT's 0.019); PT's shares there, 0.71 and about 0.63, give
// β = κ (1 − f)² / f² ≈ 0.055 and 0.064. At 0.3 (κ ≈ 0.05) c = 1/32 to 1/4 tie (0.0065–0.0085);
// the Lambert and Phong houses (κ ≈ 0.001) keep kAutoRatioPtTimeShareEyeShared's 0.12. Between, the
// GGX house (κ ≈ 0.02 at 100 k triangles, 0.009 at 1 M) moves from c = 1/32 (1/64) to 1/8 (1/32): its
// relMSE 1.1x (1.25x), its worst 8x8 block 0.5x (0.7x): a little grain for half the regional error.
constexpr double kAutoRatioRbVarianceOverPt = 0.06;
double gloss_pt_time_share(double pt_variance_kept);   // 0 where κ is not known (NaN) or not positive
double probed_pt_time_share(double base_share, double pt_variance_kept);  // the larger of the two
// κ needs this many batches of PT's probe samples; the probe takes them where they cost at most
// kAutoRatioProbeVarianceShare of the render's time (else κ is not measured).
constexpr int kAutoRatioProbeMinPtBatches = 8;
constexpr double kAutoRatioProbeVarianceShare = 0.05;
// The probe's timed work: this share of the render's time (--time, or the time --spp / --iterations
// would take, estimated from one sample and one iteration), at most kAutoRatioProbeCapSeconds.
constexpr double kAutoRatioProbeShare = 0.02;
constexpr double kAutoRatioProbeCapSeconds = 1.5;

// What bounds the round --ratio auto may choose. A render stops between rounds, so a round longer
// than its --time overshoots it (the Phong house at 1280x720: t_PT = 3 s, t_RB = 0.2 s, c = 1/128 is a
// 29 s round for a 16 s budget): the round is shrunk (N2, else N1, halved) until it fits
// round_seconds. PT alone only where the render does not count RB iterations.
struct AutoRatioBounds {
  double round_seconds = 0.0;  // the render's --time; 0: none
  bool pt_alone_allowed = true;
};

// The round --ratio auto renders with, from the measured costs: seconds per PT sample per pixel
// (whole image) and per RB iteration (eye estimate included), PT getting pt_time_share of the time
// (PT alone, or at least kAutoRatioPtTimeShareRbCostly, where t_RB > t_PT). See combined.cpp for the
// derivation.
RoundShape auto_ratio_shape(double pt_seconds_per_spp, double rb_seconds_per_iteration, double pt_time_share,
                            const AutoRatioBounds& bounds = {});

// PT's probe image: the render's view at about kAutoRatioProbePixels pixels (its own size if
// smaller), same aspect. A PT sample's cost per pixel has the same distribution over the view at any
// resolution, so t_PT = (the probe image's time per sample) · pixels / probe pixels, at a fraction of
// a full-size sample's cost (a 1280x720 sample of the rooms takes about a second).
constexpr std::size_t kAutoRatioProbePixels = 128 * 128;
struct ProbeImageSize {
  int width = 1, height = 1;
};
ProbeImageSize probe_image_size(int width, int height);

// What the probe measured and chose.
// --eye-direct auto (docs/design.md §3, "Sharing the eye vertex's direct light with RB"): the eye vertex's
// direct light is shared with RB when the render will give each pixel fewer than this many PT
// samples, else it is PT's alone. RB's patch-level direct light is smooth but blurred (a
// discretisation error that no number of iterations removes); PT's per-pixel light samples are
// unbiased but noisy until there are many of them. Measured side by side (README, issue #12): on the
// Lambert house at 640x360, 30 s, sharing is better at 40 and at 84 PT spp (relMSE 0.0026 against
// 0.0068, 0.0028 against 0.0040); on cornell-glossy at 128x128, 20 s (300 to 1200 spp) PT alone is
// better (0.0009 against 0.0028 at about 300 spp, loaded machine); on cornell-glossy at 640x360, 16 s,
// PT alone at about 110 spp (c = 1/8) reached 0.00188 where sharing (c = 1/128) had 0.0043 (the sweep,
// README): 128 was too high for it, and 96 still lies above the house's 84.
constexpr double kEyeDirectSharedBelowSpp = 96.0;
// Point, spot and sun lights cast sharp shadows, which RB's patch-level eye light blurs whatever the
// budget: shared, the Blender room (a sun through a window, a point light) at 640x360 stayed 0.015
// of relMSE off at 30 and 120 s where the path tracer's own light reached 0.0021 and 0.0003, and at
// 15 s (13 spp, below the threshold above) 0.017 against 0.0039; a window with the sun behind it at
// 15 s 0.14 against 0.002 (docs/results.md, "Who takes the eye vertex's direct light"; the render's
// own estimate held 0.12-0.7 of it). Where such lights hold at least this share of the lights' power (by
// the lights' selection power, host/scene/lights.cpp), --eye-direct auto gives the eye vertex's direct
// light to PT at any budget. The area-lit boxes and houses have none.
constexpr double kEyeDirectPtFromDeltaLightShare = 0.5;

// PT samples per pixel a combined render at ratio c will take: its --spp, its --iterations times c,
// or what fits in its --time at the probe's costs (0 where nothing bounds it: the default 64 spp).
double expected_pt_spp(const RoundShape& shape, std::uint64_t spp, std::uint64_t iterations, double seconds,
                       double pt_seconds_per_spp, double rb_seconds_per_iteration);

struct RatioProbe {
  RoundShape chosen;                                // at pt_time_share, within bounds
  double pt_time_share = 0.0;
  AutoRatioBounds bounds;                           // from the render's budget
  double pt_seconds_per_spp = 0.0;
  double rb_seconds_per_iteration = 0.0;
  std::uint32_t pt_samples = 0, rb_iterations = 0;  // the timed ones (plus one untimed RB iteration)
  ProbeImageSize pt_image;                          // where the PT samples were taken
  double pt_variance_kept = std::nan("");           // κ (gloss_pt_time_share); NaN: not measured
  std::uint64_t pt_variance_batches = 0;            // the batches κ is from
  double probe_seconds = 0.0;                       // wall time of the whole probe
  double first_launch_seconds = 0.0;                // of which the untimed first launches
};

// What the render will do, for the probe's size: seconds (0: none) and a round target in PT samples
// per pixel or RB iterations (0: none).
struct RatioProbeBudget {
  double seconds = 0.0;
  std::uint64_t spp = 0, iterations = 0;
  double pt_time_share = kAutoRatioPtTimeShareEyeShared;  // what the round is chosen for
  std::uint64_t equal_time_spp = 0;  // no budget: the time this many PT samples per pixel take
  std::uint32_t weight_mode = BP_WEIGHTS_PRODUCT;  // the render's (BP_WEIGHTS_*), for κ's samples
};

// A combined render with no budget (RenderSpec::equal_time_spp) takes as long as equal_time_spp PT
// samples per pixel alone would: that time over one round's, N1 t_PT + N2 t_RB, at least one round.
// Without costs (a resumed render: no probe) equal_time_spp / N1 rounds, rounded up.
std::uint64_t equal_time_rounds(std::uint64_t equal_time_spp, const RoundShape& shape, double pt_seconds_per_spp,
                                double rb_seconds_per_iteration);

// Times PT on `probe_pt` (a pass of its own, at probe_image_size, with the render's settings) and RB
// on the render's own pass (after an untimed PT launch of 0 samples and RB iteration, which pay the
// first launches; then at least one timed PT sample and RB iteration) and picks the round with
// auto_ratio_shape. `pixels` is the render's. Nothing stays in the render's passes: the ray-bundle
// accumulator and state (warm-up not done) are put back as they were, so the render that follows is
// the one a fixed --ratio of the chosen c gives, bit for bit.
// rb_accums: every accumulator rb adds into (one per view).
// probe_pt adds into probe_pt_accum; where it keeps the unweighted sums, κ is measured on the
// samples after the first, under the weights of the round the costs choose (probe_pt's are set).
RatioProbe probe_ratio(PathTracerPass& probe_pt, const Accumulator& probe_pt_accum, std::size_t pixels,
                       RayBundlePass& rb, const std::vector<Accumulator*>& rb_accums, const RatioProbeBudget& budget);

class CombinedPass : public ProgressivePass {
 public:
  // pt: the path tracer, or a walkthrough's path tracers (each_view.h).
  CombinedPass(ProgressivePass& pt, RayBundlePass& rb, RoundShape shape) : pt_(pt), rb_(rb), shape_(shape) {}
  // Rounds [first, first + count). The PT samples go to the path tracer in launches of at most its
  // max_batch() that end on multiples of it (at --ratio 1e4 one round alone has 10^4 samples per
  // pixel, which one launch would sum in float); RB flushes its float sums every max_batch() itself.
  BatchCounts run(std::uint64_t first, std::uint32_t count) override;
  std::uint32_t max_batch() const override;
  const Launcher& launcher() const override { return pt_.launcher(); }
  const BuiltProgram& program() const override { return pt_.program(); }
  std::vector<const ProgressivePass*> parts() const override { return {&pt_, &rb_}; }
  RoundShape shape() const { return shape_; }

 private:
  ProgressivePass& pt_;
  RayBundlePass& rb_;
  RoundShape shape_;
};

}  // namespace bp

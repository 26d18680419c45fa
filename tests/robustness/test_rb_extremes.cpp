// Ray bundles and the combination at numerical extremes: PT-to-RB ratios c = N1/N2 of 0, 1e-4 and
// 1e4; patches far smaller and far larger than a bin; 1e5 iterations (and rounds of 1e4 iterations
// or 1e4 samples at once) summed without precision loss. Every image must be finite and match a value
// derived here: the furnace's Le/(1-a) with a t-test over independent runs, or, where each estimate
// is exact, the double-precision sum of the per-iteration values within the float-summation bound.
#include "e2e/cli_runner.h"
#include "image/image.h"
#include "kernel/device_fixture.h"
#include "passes/combined.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

namespace bp::test {
namespace {

// Every statistical check in this file is one test of a family of this size, so that the whole file
// fails by chance with probability at most 0.01 (Šidák): ratios 3, bins 2.
constexpr int kStatisticalChecks = 5;
const double kUnit = std::ldexp(1.0, -24);  // float's unit roundoff

SceneMaterial lambert(float albedo, glm::vec3 le) {
  SceneMaterial m;
  m.kd = glm::vec3(albedo);
  m.ks = glm::vec3(0.0f);
  m.emission = le;
  return m;
}

double image_mean(const ImageRGB& image) {
  return std::accumulate(image.rgb.begin(), image.rgb.end(), 0.0) / double(image.rgb.size());
}

void expect_finite(const ImageRGB& image, const std::string& what) {
  for (float v : image.rgb) {
    ASSERT_TRUE(std::isfinite(v)) << what << ": a non-finite pixel";
    ASSERT_GE(v, 0.0f) << what << ": a negative pixel";
  }
}

// The |t| beyond which Student's t with `dof` degrees of freedom has two-sided probability alpha.
double t_critical(double alpha, double dof) {
  double lo = 0.0, hi = 1e3;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_two_sided_p(mid, dof) > alpha ? lo : hi) = mid;
  }
  return hi;
}

// Independent runs (different seeds) of an estimator whose expectation is `expected`: Student's t
// on their means, with the runs' own spread as the standard error. The test must also be able to
// see a 5 % error (the largest deviation it accepts must be below that; the runs here resolve about
// 1-2 %), or a pass would say nothing.
void expect_runs_match(const std::vector<double>& means, double expected, const std::string& what) {
  const int n = int(means.size());
  const double mean = std::accumulate(means.begin(), means.end(), 0.0) / n;
  double var = 0.0;
  for (double m : means) var += (m - mean) * (m - mean) / (n - 1);
  const double alpha = sidak_alpha(0.01, kStatisticalChecks);
  const double se = std::sqrt(var / n), t = (mean - expected) / se;
  EXPECT_GT(student_t_two_sided_p(t, n - 1), alpha)
      << what << ": mean " << mean << ", expected " << expected << ", standard error " << se << ", t " << t;
  EXPECT_LT(se * t_critical(alpha, n - 1), 0.05 * expected)
      << what << ": too few samples to see a 5 % error (mean " << mean << ", standard error " << se << ")";
  ::testing::Test::RecordProperty(what + ": relative standard error", std::to_string(se / expected));
}

// The Lambert furnace: a closed 2 m box, kd = a and Le everywhere, answer Le/(1-a) at every pixel.
// RB's warm-up leaves a^W of it out, 2^-40 here.
constexpr float kFurnaceAlbedo = 0.5f, kFurnaceLe = 1.0f;
constexpr std::uint32_t kFurnaceWarmup = 40;
const double kFurnaceValue = kFurnaceLe / (1.0 - kFurnaceAlbedo);
Scene furnace() { return make_closed_box(1.0f, lambert(kFurnaceAlbedo, glm::vec3(kFurnaceLe))); }

// ------------------------------------------------------------------ PT-to-RB ratios 0, 1e-4, 1e4

// --mode combined with the product weights at c = 0 (RB alone, w_RB = 1), c = 1e-4 (a round is 1
// sample and 1e4 iterations: beta = 1/(1 + 1e-4 P) ~ 1, RB carries nearly everything) and c = 1e4
// (1e4 samples and 1 iteration: beta ~ 1e-4, PT carries all but the directly seen emitters). The sum
// pt + rb stays the furnace's value at every ratio, with nothing dropped as NaN/Inf; RB always
// carries the directly seen emitter whole (the empty product: w_RB = 1), so its layer is >= Le.
TEST(RbExtremesRatio, CombinedFurnaceKeepsItsValueAtRatiosZeroTinyAndHuge) {
  struct Case { const char* name; std::uint32_t pt, rb; std::uint64_t rounds; };
  const int runs = 4, size = 4;
  for (const Case& c : {Case{"ratio 0", 0, 1, 1000}, Case{"ratio 1e-4", 1, 10000, 1}, Case{"ratio 1e4", 10000, 1, 1}}) {
    std::vector<double> means;
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < runs; ++k) {
      CombinedSettings cs;
      cs.weight_mode = BP_WEIGHTS_PRODUCT;
      cs.pt_samples_per_round = c.pt;
      cs.rb_iterations_per_round = c.rb;
      cs.rounds = c.rounds;
      cs.seed = 300u + 17u * std::uint32_t(k);
      cs.warmup = kFurnaceWarmup;
      cs.patch_size = 2.0f;  // 4 patches per triangle: the 1e4 iterations of a round at c = 1e-4 stay quick
      CombinedRun run = render_combined(furnace(), size, size, cs);
      EXPECT_EQ(run.outcome.nonfinite_samples, 0u) << c.name;
      expect_finite(run.pt, std::string(c.name) + ", pt layer");
      expect_finite(run.rb, std::string(c.name) + ", rb layer");
      expect_finite(run.combined, c.name);
      for (float v : run.rb.rgb)
        ASSERT_GE(v, kFurnaceLe * (1.0 - run.rb_max_batch * kUnit)) << c.name << ": RB lost the directly seen emitter";
      if (c.pt == 0) {  // no PT sample was taken: its layer is exactly empty
        for (float v : run.pt.rgb) ASSERT_EQ(v, 0.0f) << c.name;
        EXPECT_EQ(run.outcome.rounds, c.rounds);
      }
      means.push_back(image_mean(run.combined));
    }
    RecordProperty(std::string(c.name) + ": seconds",
                   std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()));
    expect_runs_match(means, kFurnaceValue, c.name);
  }
}

// c = 0 is ray bundles alone, unweighted: bit for bit the image of the RB pass on its own (as
// --mode rb gives it) with the same seed, patches, bins and warm-up.
TEST(RbExtremesRatio, RatioZeroIsTheRayBundlePassAlone) {
  CombinedSettings cs;
  cs.pt_samples_per_round = 0;
  cs.rb_iterations_per_round = 1;
  cs.rounds = 200;
  cs.seed = 41u;
  cs.bins = 24;
  cs.warmup = 8;
  cs.patch_size = 0.25f;
  const Scene scene = make_glossy_light_box();
  CombinedRun combined = render_combined(scene, 12, 12, cs);
  auto rig = make_bundle_rig(scene, cs.patch_size, cs.bins, cs.seed, 12, 12, cs.warmup);
  RenderRun alone = render_rb(*rig, cs.rounds);
  EXPECT_GT(image_mean(alone.image), 0.0);
  EXPECT_EQ(combined.rb.rgb, alone.image.rgb);
  EXPECT_EQ(combined.combined.rgb, alone.image.rgb);
  const RoundShape shape = round_shape(0.0);
  EXPECT_EQ(shape.pt_samples, 0u);
  EXPECT_EQ(shape.rb_iterations, 1u);
  const CombinedWeights w = combined_weights(BP_WEIGHTS_PRODUCT, shape);
  EXPECT_EQ(w.mode, std::uint32_t(BP_WEIGHTS_NONE));
  EXPECT_TRUE(std::isfinite(w.ratio_n2_over_n1));
}

// The command line: --ratio 0 renders the same image as --mode rb (and counts no samples); 1e-4 and
// 1e4 run with the round shapes they name and give finite images.
TEST(RbExtremesRatio, CommandLineAcceptsZeroTinyAndHugeRatios) {
  const std::string dir = fresh_dir("rb_extremes_ratio");
  const std::string scene = std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf";
  const std::string common = "render " + scene + " --width 8 --height 8 --patch-size 0.3 --bins 24 --seed 5 ";
  CliResult rb = run_cli(common + "--mode rb --iterations 48 --out " + dir + "/rb");
  ASSERT_EQ(rb.exit_code, 0) << rb.output;
  CliResult zero = run_cli(common + "--mode combined --ratio 0 --iterations 48 --out " + dir + "/zero --stats " + dir +
                           "/zero.json");
  ASSERT_EQ(zero.exit_code, 0) << zero.output;
  EXPECT_EQ(read_exr(dir + "/zero.exr").rgb, read_exr(dir + "/rb.exr").rgb);
  for (float v : read_exr(dir + "/zero.exr", "pt").rgb) ASSERT_EQ(v, 0.0f);
  nlohmann::json stats = nlohmann::json::parse(std::ifstream(dir + "/zero.json"));
  EXPECT_EQ(stats["spp"], 0);
  EXPECT_EQ(stats["iterations"], 48);
  EXPECT_EQ(stats["ratio"], 0.0);

  struct Case { std::string ratio, count, name; std::uint64_t spp, iterations; };
  for (const Case& c : {Case{"1/10000", "--spp 1", "tiny", 1, 10000}, Case{"1e4", "--iterations 1", "huge", 10000, 1}}) {
    CliResult r = run_cli(common + "--mode combined --ratio " + c.ratio + " " + c.count + " --out " + dir + "/" + c.name +
                          " --stats " + dir + "/" + c.name + ".json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    nlohmann::json s = nlohmann::json::parse(std::ifstream(dir + "/" + c.name + ".json"));
    EXPECT_EQ(s["spp"], c.spp) << c.ratio;
    EXPECT_EQ(s["iterations"], c.iterations) << c.ratio;
    EXPECT_EQ(s["nan_or_inf_samples"], 0) << c.ratio;
    for (const char* layer : {"", "pt", "rb"}) expect_finite(read_exr(dir + "/" + c.name + ".exr", layer), c.ratio + " " + layer);
    EXPECT_GT(image_mean(read_exr(dir + "/" + c.name + ".exr")), 0.0) << c.ratio;
  }
}

// ------------------------------------------------------------------ patches and bins

// The floor of the closed 2 m box reflects (Lambert, albedo a, no emission); the other five walls
// emit Le and reflect nothing. The floor sees walls over its whole hemisphere, so its radiance is
// exactly a Le -- one bounce, no longer paths, whose products of rare large transfers would make the
// runs' means heavy-tailed -- and the camera, 1 m above its centre looking straight down, sees floor only.
constexpr float kFloorAlbedo = 0.6f, kWallLe = 1.5f;
Scene lit_floor() {
  Scene scene = make_closed_box(1.0f, lambert(0.0f, glm::vec3(kWallLe)));
  scene.materials.push_back(lambert(kFloorAlbedo, glm::vec3(0.0f)));
  for (SceneTriangle& t : scene.triangles)
    if (t.p[0].y == -1.0f && t.p[1].y == -1.0f && t.p[2].y == -1.0f) t.material = 1;
  scene.camera.position = glm::vec3(0.0f);
  scene.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
  scene.camera.yfov = 1.4f;  // sees |x|, |z| <= tan(0.7) = 0.84 of the floor's 1
  return scene;
}

// RB alone with patches far smaller than a bin (a patch is ~1/50 of a bin: a bin centre lands on it
// in a few percent of the iterations, and then it receives ~50x its mean) and with one patch per
// triangle, each covering ~170 bins: both images converge to a Le.
TEST(RbExtremesBins, ImageIsRightForPatchesFarSmallerAndFarLargerThanABin) {
  struct Case { const char* name; float patch_size; std::uint32_t bins; std::uint64_t iterations; };
  const int runs = 6;
  for (const Case& c : {Case{"patches far smaller than a bin", 0.35f, 4, 3000},
                        Case{"patches far larger than a bin", 10.0f, 32, 6000}}) {
    std::vector<double> means;
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < runs; ++k) {
      auto rig = make_bundle_rig(lit_floor(), c.patch_size, c.bins, 500u + 31u * std::uint32_t(k), 8, 8, 2);
      if (k == 0) {
        const double bin = 2.0 * rig->geometry.radius / rig->pass->bins();
        const double patch_area = rig->geometry.element_area / double(rig->geometry.patch_element.size());
        RecordProperty(std::string(c.name) + ": bins per patch", std::to_string(patch_area / (bin * bin)));
      }
      RenderRun run = render_rb(*rig, c.iterations);
      EXPECT_EQ(run.outcome.nonfinite_samples, 0u) << c.name;
      expect_finite(run.image, c.name);
      means.push_back(image_mean(run.image));
    }
    RecordProperty(std::string(c.name) + ": seconds",
                   std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()));
    expect_runs_match(means, double(kFloorAlbedo) * kWallLe, c.name);
  }
}

// ------------------------------------------------------------------ accumulation precision

// A closed box whose walls emit Le and reflect nothing: every eye estimate is exactly Le (Le plus a
// reflection term of exactly 0), in every iteration, sample and pixel. Three channels, three values
// whose repeated float sums round differently.
const glm::vec3 kExactLe(0.1f, 1.0f / 3.0f, 2.9f);
Scene black_emitting_box() { return make_closed_box(1.0f, lambert(0.0f, kExactLe)); }

// The double-precision sum of n copies of v (exact: 24 + 17 bits fit in a double).
double double_sum(float v, std::uint64_t n) {
  double s = 0.0;
  for (std::uint64_t i = 0; i < n; ++i) s += double(v);
  return s;
}

// What one float accumulator over all n would hold.
float float_sum(float v, std::uint64_t n) {
  float s = 0.0f;
  for (std::uint64_t i = 0; i < n; ++i) s += v;
  return s;
}

// Summing terms of one sign recursively in float errs by at most (m - 1) u of the sum for m terms;
// groups of at most m terms added into doubles keep that bound for any count (plus n 2^-53 for the
// doubles, and u for the final conversion of a mean to float).
double group_bound(std::uint32_t m, std::uint64_t n) { return double(m - 1) * kUnit + double(n) * std::ldexp(1.0, -53); }

// 1e5 iterations of the RB pass, the way --mode rb runs them (the render loop's batches), against the
// double sum of the same per-iteration values. The first 64 iterations, one at a time, show that each
// value is exactly Le; a single float accumulator over 1e5 of them would be off by ~1e-4 to 1e-3,
// thousands of times the bound (checked below, so the test can tell).
TEST(RbExtremesPrecision, HundredThousandIterationsLoseNoPrecision) {
  const std::uint64_t n = 100000, one_by_one = 64;
  auto rig = make_bundle_rig(black_emitting_box(), 2.0f, 4, 7u, 2, 2, 0);
  const std::size_t values = rig->accum.sum.size();
  for (std::uint64_t i = 0; i < one_by_one; ++i) {
    const std::vector<double> before = rig->accum.sum;
    rig->pass->run(i, 1);
    for (std::size_t j = 0; j < values; ++j)
      ASSERT_EQ(rig->accum.sum[j] - before[j], double(kExactLe[int(j % 3)])) << "iteration " << i << ", value " << j;
  }
  std::atomic<bool> never{false};
  RenderOutcome outcome = run_progressive(*rig->pass, RenderBudget{n, 0.0}, never, nullptr, one_by_one);
  ASSERT_EQ(outcome.rounds, n);
  ASSERT_EQ(rig->accum.samples_per_pixel, n);
  EXPECT_EQ(outcome.nonfinite_samples, 0u);
  const double bound = group_bound(rig->pass->max_batch(), n);
  double worst = 0.0;
  for (std::size_t j = 0; j < values; ++j) {
    const float le = kExactLe[int(j % 3)];
    const double exact = double_sum(le, n);
    const double error = std::fabs(rig->accum.sum[j] - exact) / exact;
    worst = std::max(worst, error);
    EXPECT_LE(error, bound) << "value " << j << " (Le " << le << "): sum " << rig->accum.sum[j] << ", exact " << exact;
    EXPECT_LE(std::fabs(rig->accum.mean().rgb[j] - le), (bound + kUnit) * le) << "value " << j;
  }
  RecordProperty("worst relative error", std::to_string(worst));
  RecordProperty("bound", std::to_string(bound));
  double float_error = 0.0;
  for (int c = 0; c < 3; ++c)
    float_error = std::max(float_error, std::fabs(double(float_sum(kExactLe[c], n)) - double_sum(kExactLe[c], n)) /
                                            double_sum(kExactLe[c], n));
  EXPECT_GT(float_error, 100.0 * bound) << "a plain float sum would pass too: the test could not tell";
}

// The extreme ratios hand a pass 1e4 rounds at once: at c = 1e-4 a round is 1e4 RB iterations, at
// c = 1e4 it is 1e4 PT samples per pixel. Both still reach the doubles in float groups no larger than
// the passes' own batches. The directly seen emitter is RB's alone under the product weights (the PT
// layer stays exactly 0); with the weights off (none), every PT sample is exactly Le too.
TEST(RbExtremesPrecision, RoundsOfTenThousandAtOnceLoseNoPrecision) {
  struct Case { const char* name; std::uint32_t weights, pt, rb; std::uint64_t rounds; };
  for (const Case& c : {Case{"ratio 1e-4", BP_WEIGHTS_PRODUCT, 1, 10000, 2}, Case{"ratio 1e4, weights none", BP_WEIGHTS_NONE, 10000, 1, 3}}) {
    CombinedSettings cs;
    cs.weight_mode = c.weights;
    cs.pt_samples_per_round = c.pt;
    cs.rb_iterations_per_round = c.rb;
    cs.rounds = c.rounds;
    cs.warmup = 0;
    cs.bins = 4;
    cs.patch_size = 2.0f;
    CombinedRun run = render_combined(black_emitting_box(), 2, 2, cs);
    ASSERT_EQ(run.outcome.rounds, c.rounds) << c.name;
    EXPECT_EQ(run.outcome.nonfinite_samples, 0u) << c.name;
    const std::uint64_t iterations = c.rounds * c.rb, samples = c.rounds * c.pt;
    const double rb_bound = group_bound(run.rb_max_batch, iterations) + kUnit;
    const double pt_bound = group_bound(run.pt_max_batch, samples) + kUnit;
    for (std::size_t j = 0; j < run.rb.rgb.size(); ++j) {
      const float le = kExactLe[int(j % 3)];
      EXPECT_LE(std::fabs(run.rb.rgb[j] - le), rb_bound * le) << c.name << ", rb value " << j << ": " << run.rb.rgb[j];
      if (c.weights == BP_WEIGHTS_NONE)
        EXPECT_LE(std::fabs(run.pt.rgb[j] - le), pt_bound * le) << c.name << ", pt value " << j << ": " << run.pt.rgb[j];
      else
        EXPECT_EQ(run.pt.rgb[j], 0.0f) << c.name << ", pt value " << j;
    }
    // One float sum over a whole round would not pass.
    const std::uint64_t per_round = std::max(c.pt, c.rb);
    double float_error = 0.0;
    for (int ch = 0; ch < 3; ++ch)
      float_error = std::max(float_error, std::fabs(double(float_sum(kExactLe[ch], per_round)) /
                                                        double_sum(kExactLe[ch], per_round) - 1.0));
    EXPECT_GT(float_error, 4.0 * (c.weights == BP_WEIGHTS_NONE ? pt_bound : rb_bound))
        << c.name << ": the check could not tell a float sum over a whole round";
  }
}

}  // namespace
}  // namespace bp::test

// --target-error and the error estimate as a user meets them: bad values, a render that stops at its
// error (checked against the error two independent renders actually have), the stats and the EXR's
// stderr layer, and the batch statistics through a checkpoint.
#include "e2e/cli_runner.h"
#include "estimate_reference.h"
#include "image/image.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <fstream>
#include <vector>

namespace bp::test {
namespace {

const std::string kBox = std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf ";

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

TEST(TargetError, BadValuesExitTwoWithOneLine) {
  struct Case { std::string args, needle; };
  const Case cases[] = {
      {"--target-error 0", "--target-error"},
      {"--target-error -0.001", "--target-error"},
      {"--target-error nan", "--target-error"},
      {"--target-error inf", "--target-error"},
      {"--target-error abc", "--target-error"},
      {"--target-error", "--target-error"},
      {"--target-error 0.001 --spp 16", "--spp"},
      {"--mode rb --target-error 0.001 --iterations 16", "--iterations"},
      {"--mode combined --spp 4 --target-error 0.01", "--target-error"},
      {"--error-batch 0", "--error-batch"},
      {"--error-levels 0", "--error-levels"},
  };
  for (const Case& c : cases) {
    CliResult r = run_cli("render " + kBox + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << c.args << "\n" << r.output;
  }
}

// Two renders with independent seeds stop at --target-error 0.001; the error they really have is
// measured from their difference, E[(I1 − I2)²] = Var1 + Var2 (the path tracer is unbiased, so this
// is its whole relMSE; the combination's RB share adds a bias of about 0.00003 here, README, "Error
// estimates"), with R ≈ (I1 + I2)/2 in docs/design.md §7's denominator. The issue asks for
// 0.0005..0.0015; each run's own estimate must be within 1.5x of the measured value. The path tracer,
// and the combination at c = 1, whose RB batches are 64 rounds: before PT's and RB's layers were
// estimated from batches of their own it waited for eight of those, 512 rounds, and stopped at 0.0004.
// It also waits for the check of RB's bias (six of RB's batches: 384 rounds at 64, where it stopped
// at 0.00047), so its batches here are of 16 rounds, and the check counts from round 96.
TEST(TargetError, CornellBoxStopsNearTheTargetError) {
  const std::string dir = fresh_dir("target_error_box");
  for (const std::string mode : {"--mode pt", "--mode combined --ratio 1 --error-batch 16"}) {
    double estimated[2];
    for (int s = 0; s < 2; ++s) {
      const std::string out = dir + "/seed" + std::to_string(s + 1);
      CliResult r = run_cli("render " + kBox + mode + " --width 128 --height 128 --target-error 0.001 --seed " +
                            std::to_string(s + 1) + " --out " + out + " --stats " + out + ".json");
      ASSERT_EQ(r.exit_code, 0) << r.output;
      nlohmann::json stats = read_json(out + ".json");
      EXPECT_EQ(stats["target_reached"], true) << mode;
      EXPECT_GE(stats["error_estimate"]["degrees_of_freedom"].get<double>(), 7.0) << mode;
      estimated[s] = stats["estimated_rel_mse"].get<double>();
      EXPECT_LE(estimated[s], 0.001) << mode;
    }
    const ImageRGB a = read_exr(dir + "/seed1.exr"), b = read_exr(dir + "/seed2.exr");
    double sum = 0.0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
      const double d = double(a.rgb[i]) - b.rgb[i], r = 0.5 * (double(a.rgb[i]) + b.rgb[i]);
      sum += 0.5 * d * d / (r * r + 0.01);  // (Var1 + Var2) / 2: each run's relMSE, on average
    }
    const double measured = sum / double(a.rgb.size());
    EXPECT_GT(measured, 0.0005) << mode;
    EXPECT_LT(measured, 0.0015) << mode;
    const double mean_estimate = 0.5 * (estimated[0] + estimated[1]);
    EXPECT_LT(mean_estimate, 1.5 * measured) << mode << ": measured " << measured;
    EXPECT_GT(mean_estimate, measured / 1.5) << mode << ": measured " << measured;
    // The stderr layer is the per-pixel standard error: its mean square over the image, each over the
    // smaller of the pixel and its 8 neighbours' mean, squared (error_estimate.h), is the relMSE estimated
    // less the check of RB's layer against PT's estimate of its share (no variance: a bias).
    const ImageRGB se = read_exr(dir + "/seed1.exr", "stderr");
    ASSERT_EQ(se.rgb.size(), a.rgb.size());
    std::vector<double> variance(se.rgb.size());
    for (std::size_t i = 0; i < se.rgb.size(); ++i) variance[i] = double(se.rgb[i]) * se.rgb[i];
    const nlohmann::json bias = read_json(dir + "/seed1.json")["error_estimate"]["rb_bias_rel_mse"];
    if (mode == "--mode pt") {
      EXPECT_TRUE(bias.is_null());  // a combined render's, once it has the batches
      EXPECT_NEAR(estimated_rel_mse_of(a, variance), estimated[0], 1e-3 * estimated[0]) << mode;
    } else {
      // The consistent level (the default, image/share_correction.h): the estimate sums per-pixel
      // error terms that are unbiased but may be negative (a residual below PT's noise), the layer
      // clamps each at 0 to take its root: its mean square is the estimate or more, not far more.
      const double layer = estimated_rel_mse_of(a, variance);
      EXPECT_GE(layer, estimated[0] * (1.0 - 1e-3)) << mode;
      EXPECT_LT(layer, 1.5 * estimated[0]) << mode;
    }
  }
}

// Under a level that keeps RB's bias (--rb-level regional), a combined render's estimate holds RB's
// bias only once the check of RB's layer against PT's estimate of its share has paired
// kRbBiasMinPairedBatches of RB's batches: --target-error waits for it, and a render too short for it
// says that the estimate lacks it. (The consistent default's estimate holds what is left of the bias
// from its first batches: nothing to wait for.) At c = 1/8, PT's variance is most of the
// estimate, so an easy target has its 7 degrees of freedom after about 16 rounds (where it stopped
// before the wait); RB's batches of 32 iterations are 4 rounds: the check counts from the sixth, 24.
TEST(TargetError, CombinedWaitsForTheCheckOfRbsBias) {
  const std::string dir = fresh_dir("target_error_rb_bias");
  const std::string common =
      "render " + kBox + "--mode combined --ratio 1/8 --rb-level regional --width 32 --height 32 --error-batch 32 ";
  CliResult r = run_cli(common + "--target-error 0.5 --out " + dir + "/target --stats " + dir + "/target.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nlohmann::json stats = read_json(dir + "/target.json");
  EXPECT_EQ(stats["target_reached"], true);
  EXPECT_GE(stats["error_estimate"]["rb_bias_check"]["batches"].get<int>(), 5) << stats["error_estimate"].dump();
  EXPECT_GE(stats["rounds"].get<int>(), 24);
  EXPECT_TRUE(stats["error_estimate"]["rb_bias_rel_mse"].is_number());
  EXPECT_EQ(r.output.find("not checked yet"), std::string::npos) << r.output;
  // 8 rounds: two of RB's batches, one pair.
  r = run_cli(common + "--spp 8 --out " + dir + "/short --stats " + dir + "/short.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(read_json(dir + "/short.json")["error_estimate"]["rb_bias_rel_mse"].is_null());
  EXPECT_NE(r.output.find("the ray bundles' bias not checked yet, not included (1 of 5 batch pairs)"), std::string::npos)
      << r.output;
}

// --time caps a target that cannot be reached in it: the render ends by time, and says so.
TEST(TargetError, TimeCapsAnUnreachableTarget) {
  const std::string dir = fresh_dir("target_error_cap");
  CliResult r = run_cli("render " + kBox + "--mode pt --width 32 --height 32 --target-error 1e-12 --time 3 --out " + dir +
                        "/img --stats " + dir + "/s.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nlohmann::json stats = read_json(dir + "/s.json");
  EXPECT_EQ(stats["target_reached"], false);
  // Only the cap ends it, at the batch end nearest 3 s: past half of it (batches at most double). A
  // lower bound, not a timing test.
  EXPECT_GE(stats["render_seconds"].get<double>(), 1.5);
  // On a loaded machine the first launches may fill the 3 s: the estimate needs two batches.
  if (stats["estimated_rel_mse"].is_number()) {
    EXPECT_GT(stats["estimated_rel_mse"].get<double>(), 1e-12);
    EXPECT_NE(r.output.find("--target-error not reached"), std::string::npos) << r.output;
  }
}

// A render stopped and resumed continues the same batches: the estimate and the stderr layer equal
// those of an uninterrupted render, bit for bit, in every mode. (The combined renders name their
// --eye-direct: under auto the first part's 32 spp and the whole's 96 could choose differently,
// kEyeDirectSharedBelowSpp, and a resumed render keeps the first part's choice.)
TEST(TargetError, EstimateSurvivesACheckpoint) {
  const std::string dir = fresh_dir("target_error_checkpoint");
  const std::string common = "render " + std::string(BP_SOURCE_DIR) + "/scenes/cornell-glossy.gltf --width 24 --height 18 ";
  for (const std::string mode : {"--mode pt --spp", "--mode rb --error-batch 16 --iterations",
                                 "--mode combined --ratio 1/4 --eye-direct shared --error-batch 16 --spp"}) {
    ASSERT_EQ(run_cli(common + mode + " 96 --out " + dir + "/whole --stats " + dir + "/whole.json").exit_code, 0) << mode;
    ASSERT_EQ(run_cli(common + mode + " 32 --checkpoint " + dir + "/ck --out " + dir + "/first").exit_code, 0) << mode;
    CliResult r = run_cli(common + mode + " 96 --resume " + dir + "/ck --stats " + dir + "/rest.json --out " + dir + "/rest");
    ASSERT_EQ(r.exit_code, 0) << mode << "\n" << r.output;
    nlohmann::json whole = read_json(dir + "/whole.json"), rest = read_json(dir + "/rest.json");
    ASSERT_TRUE(whole["estimated_rel_mse"].is_number()) << mode;
    EXPECT_EQ(rest["estimated_rel_mse"], whole["estimated_rel_mse"]) << mode;
    EXPECT_EQ(rest["error_estimate"], whole["error_estimate"]) << mode;
    EXPECT_EQ(read_exr(dir + "/rest.exr", "stderr").rgb, read_exr(dir + "/whole.exr", "stderr").rgb) << mode;
  }
}

}  // namespace
}  // namespace bp::test

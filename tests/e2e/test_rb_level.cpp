// --rb-level (image/rb_level.h) through the CLI, in the furnace (tests/data/gltf/good/furnace.gltf:
// every pixel reads Le / (1 - a) = 2): PT's estimate of RB's share agrees with RB's level, the
// corrected image keeps the furnace's value, and the written image is pt + s·rb with the stats' s.
#include "e2e/cli_runner.h"
#include "image/image.h"
#include "image/regions.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <fstream>
#include <vector>

namespace bp::test {
namespace {

const std::string kFurnace = std::string(BP_SOURCE_DIR) + "/tests/data/gltf/good/furnace.gltf ";
constexpr double kFurnaceValue = 2.0;  // Le / (1 - a), Le = 1, a = 0.5

double image_mean(const ImageRGB& image) {
  double sum = 0.0;
  for (float v : image.rgb) sum += v;
  return sum / double(image.rgb.size());
}

struct SeedStatistics {
  double sum = 0.0, sum_sq = 0.0;
  int n = 0;
  void add(double x) { sum += x, sum_sq += x * x, ++n; }
  double mean() const { return sum / n; }
  double standard_error() const { return std::sqrt(std::max(0.0, (sum_sq - sum * sum / n) / (n - 1)) / n); }
};

// Eight seeds at N2/N1 = 1 (RB's weighted layer about a fifth of the image; its level varies by a
// few percent between seeds through the per-vertex beta, PT's by a few tenths): a t-test across
// seeds of PT's level less RB's, and of the corrected image's mean against 2, with one factor
// (corrected), with the regional field (8x8 regions of 2x2 pixels: PT's estimate of each region's
// share from 256 samples), and with the consistent level (the default: the regional field, then the
// share corrected down to each pixel). A PT share taken without its weighted part (level 2 instead
// of 0.4), or RB's layer scaled twice, fails them.
TEST(RbLevelCli, FurnaceLevelsAgreeAndTheCorrectedImageKeepsTheFurnacesValue) {
  const std::string dir = fresh_dir("rb_level_furnace");
  constexpr int kSeeds = 8;
  const double alpha = sidak_alpha(1e-3, 4);
  SeedStatistics level_difference, corrected_mean, regional_mean, consistent_mean;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const std::string out = dir + "/s" + std::to_string(seed);
    const std::string render = "render " + kFurnace + "--width 16 --height 16 --mode combined --ratio 1 --spp 64 --seed " +
                               std::to_string(seed);
    CliResult r = run_cli(render + " --rb-level corrected --out " + out + " --stats " + out + ".json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json level = nlohmann::json::parse(std::ifstream(out + ".json"))["rb_level"];
    ASSERT_EQ(level["mode"], "corrected");
    level_difference.add(level["pt"][0].get<double>() - level["rb"][0].get<double>());
    corrected_mean.add(image_mean(read_exr(out + ".exr")));
    CliResult regional = run_cli(render + " --rb-level regional --out " + out + "r --stats " + out + "r.json");
    ASSERT_EQ(regional.exit_code, 0) << regional.output;
    ASSERT_EQ(nlohmann::json::parse(std::ifstream(out + "r.json"))["rb_level"]["mode"], "regional");
    regional_mean.add(image_mean(read_exr(out + "r.exr")));
    CliResult consistent = run_cli(render + " --out " + out + "c --stats " + out + "c.json");
    ASSERT_EQ(consistent.exit_code, 0) << consistent.output;
    ASSERT_EQ(nlohmann::json::parse(std::ifstream(out + "c.json"))["rb_level"]["mode"], "consistent");
    consistent_mean.add(image_mean(read_exr(out + "c.exr")));
  }
  const double t_levels = level_difference.mean() / level_difference.standard_error();
  const double t_image = (corrected_mean.mean() - kFurnaceValue) / corrected_mean.standard_error();
  const double t_regional = (regional_mean.mean() - kFurnaceValue) / regional_mean.standard_error();
  const double t_consistent = (consistent_mean.mean() - kFurnaceValue) / consistent_mean.standard_error();
  std::printf("consistent %.5f +- %.5f (t %.2f)\n", consistent_mean.mean(), consistent_mean.standard_error(), t_consistent);
  std::printf("PT - RB level %.5f +- %.5f (t %.2f); corrected image %.5f +- %.5f (t %.2f); regional %.5f +- %.5f (t %.2f)\n",
              level_difference.mean(), level_difference.standard_error(), t_levels, corrected_mean.mean(),
              corrected_mean.standard_error(), t_image, regional_mean.mean(), regional_mean.standard_error(), t_regional);
  EXPECT_GT(student_t_two_sided_p(t_levels, kSeeds - 1), alpha);
  EXPECT_GT(student_t_two_sided_p(t_image, kSeeds - 1), alpha);
  EXPECT_GT(student_t_two_sided_p(t_regional, kSeeds - 1), alpha);
  EXPECT_GT(student_t_two_sided_p(t_consistent, kSeeds - 1), alpha);
  // Power: the image mean's standard error is under 0.5 % of its value, so a 2 % bias is t > 4.
  EXPECT_LT(corrected_mean.standard_error(), 0.005 * kFurnaceValue);
  EXPECT_LT(regional_mean.standard_error(), 0.005 * kFurnaceValue);
  EXPECT_LT(consistent_mean.standard_error(), 0.005 * kFurnaceValue);
}

// The image written is pt + s·rb per channel with the stats' factors s (corrected), and pt + rb (own).
TEST(RbLevelCli, WrittenImageIsPtPlusTheFactorTimesRb) {
  const std::string dir = fresh_dir("rb_level_layers");
  for (const std::string mode : {"corrected", "own"}) {
    const std::string out = dir + "/" + mode;
    CliResult r = run_cli("render " + kFurnace + "--width 12 --height 10 --mode combined --ratio 1/2 --spp 16 " +
                          "--rb-level " + mode + " --out " + out + " --stats " + out + ".json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json level = nlohmann::json::parse(std::ifstream(out + ".json"))["rb_level"];
    ASSERT_EQ(level["mode"], mode);
    const ImageRGB image = read_exr(out + ".exr"), pt = read_exr(out + ".exr", "pt"), rb = read_exr(out + ".exr", "rb");
    ASSERT_EQ(image.rgb.size(), pt.rgb.size());
    ASSERT_EQ(image.rgb.size(), rb.rgb.size());
    double largest_factor_deviation = 0.0;
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
      const double s = mode == "own" ? 1.0 : level["factors"][i % 3].get<double>();
      largest_factor_deviation = std::max(largest_factor_deviation, std::fabs(s - 1.0));
      EXPECT_NEAR(image.rgb[i], pt.rgb[i] + s * rb.rgb[i], 1e-5 * std::fabs(image.rgb[i])) << mode << " value " << i;
    }
    if (mode == "corrected") {
      EXPECT_GT(largest_factor_deviation, 0.0) << "the correction did nothing";
    }
  }
  // regional: each region's RB layer in the image is its factor times RB's own, Σ (image − pt) =
  // s_r Σ rb over the region (the field's fixed point, image/rb_level.h), and the field is not one
  // constant.
  {
    const std::string out = dir + "/regional";
    CliResult r = run_cli("render " + kFurnace + "--width 12 --height 10 --mode combined --ratio 1/2 --spp 16 " +
                          "--rb-level regional --regions 3 --out " + out + " --stats " + out + ".json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json level = nlohmann::json::parse(std::ifstream(out + ".json"))["rb_level"];
    ASSERT_EQ(level["mode"], "regional");
    ASSERT_EQ(level["factors"].size(), 9u);
    const ImageRGB image = read_exr(out + ".exr"), pt = read_exr(out + ".exr", "pt"), rb = read_exr(out + ".exr", "rb");
    const RegionGrid grid = RegionGrid::over(12, 10, 3, 3);
    std::vector<double> rb_layer(image.rgb.size());
    for (std::size_t i = 0; i < rb_layer.size(); ++i) rb_layer[i] = double(image.rgb[i]) - pt.rgb[i];
    const std::vector<double> scaled = grid.sums(rb_layer), own = grid.sums(rb.rgb);
    double least = INFINITY, largest = -INFINITY;
    for (std::size_t b = 0; b < grid.count(); ++b)
      for (std::size_t c = 0; c < 3; ++c) {
        const double factor = level["factors"][b][c].get<double>();
        EXPECT_NEAR(scaled[b * 3 + c] / own[b * 3 + c], factor, 1e-3) << "region " << b << " channel " << c;
        least = std::min(least, factor);
        largest = std::max(largest, factor);
      }
    EXPECT_GT(largest - least, 1e-3) << "the regions' factors are all one value";
  }
  CliResult bad = run_cli("render " + kFurnace + "--mode combined --spp 1 --rb-level maybe --out " + dir + "/bad");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--rb-level"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace bp::test

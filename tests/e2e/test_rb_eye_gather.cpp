// --rb-eye-gather as a user meets it: the eye estimate in blocks (the default) and every iteration
// give the same image to float rounding, layer by layer, on a scene with Lambert and Phong eye
// vertices; a bad value exits 2 with one line.
#include "e2e/cli_runner.h"
#include "image/image.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>

namespace bp::test {
namespace {

TEST(RbEyeGather, BlocksAndEveryIterationGiveTheSameImage) {
  const std::string dir = fresh_dir("rb_eye_gather");
  const std::string common = "render " + std::string(BP_SOURCE_DIR) +
                             "/scenes/cornell-glossy.gltf --width 40 --height 30 --mode combined --ratio 1/8 --spp 6 "
                             "--eye-direct shared --layers all --seed 4 ";
  for (const std::string gather : {"blocks", "every"}) {
    CliResult r = run_cli(common + "--rb-eye-gather " + gather + " --out " + dir + "/" + gather + " --stats " + dir +
                          "/" + gather + ".json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir + "/" + gather + ".json"))["rb_eye_gather"], gather);
  }
  for (const std::string layer : {"", "rb", "rb_raw"}) {
    const ImageRGB a = read_exr(dir + "/blocks.exr", layer), b = read_exr(dir + "/every.exr", layer);
    ASSERT_EQ(a.rgb.size(), b.rgb.size()) << layer;
    double worst = 0.0, total = 0.0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
      worst = std::max(worst, std::fabs(double(a.rgb[i]) - b.rgb[i]) / (std::fabs(double(b.rgb[i])) + 1e-3));
      total += b.rgb[i];
    }
    EXPECT_GT(total, 0.0) << layer;
    EXPECT_LT(worst, 1e-4) << "layer '" << layer << "'";
  }
}

TEST(RbEyeGather, BadValueExitsTwoWithOneLine) {
  CliResult r = run_cli("render " + std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf --rb-eye-gather sometimes");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--rb-eye-gather"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

}  // namespace
}  // namespace bp::test

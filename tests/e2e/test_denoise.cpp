// `render --denoise` and the albedo and normal layers every render writes (image/denoiser.h,
// docs/design.md §13), through the CLI as a user meets them.
#include "e2e/cli_runner.h"
#include "image/denoiser.h"
#include "image/image.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace bp::test {
namespace {

namespace fs = std::filesystem;
const std::string kCornell = std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf";

// Whether OpenImageDenoise can be opened here; CI (scripts/test.sh) installs it and sets
// BUNDLEPATH_TEST_REQUIRE_OIDN, so that there a missing library fails rather than skips.
bool denoiser_available(std::string& why) {
  try {
    Denoiser::open();
    return true;
  } catch (const DenoiserUnavailable& e) {
    why = e.what();
    return false;
  }
}
#define REQUIRE_DENOISER()                                                              \
  do {                                                                                  \
    std::string why;                                                                    \
    if (!denoiser_available(why)) {                                                     \
      if (std::getenv("BUNDLEPATH_TEST_REQUIRE_OIDN")) FAIL() << why;                   \
      GTEST_SKIP() << why;                                                              \
    }                                                                                   \
  } while (0)

TEST(Denoise, WithoutTheLibraryExitsTwoSayingWhatToInstallAndWritesNothing) {
  const std::string dir = fresh_dir("denoise_missing");
  CliResult r = run_cli("render " + kCornell + " --width 16 --height 16 --spp 1 --denoise --out " + dir + "/x",
                        "BUNDLEPATH_OIDN_LIBRARY=" + dir + "/no-such-folder");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--denoise needs OpenImageDenoise"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("scripts/setup.sh --oidn"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(Denoise, EveryRenderWritesFirstHitAlbedoAndNormalLayers) {
  const std::string dir = fresh_dir("feature_layers");
  CliResult r = run_cli("render " + kCornell + " --width 32 --height 32 --spp 2 --mode pt --out " + dir + "/cb");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> names = exr_layer_names(dir + "/cb.exr");
  for (const char* layer : {"albedo", "normal"})
    EXPECT_NE(std::find(names.begin(), names.end(), layer), names.end()) << layer;
  const ImageRGB albedo = read_exr(dir + "/cb.exr", "albedo"), normal = read_exr(dir + "/cb.exr", "normal");
  for (float v : albedo.rgb) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
  // A pixel's normal is the mean of its rays' unit normals (0 where a ray leaves the box); the
  // middle of the image is the back wall's, facing the camera (which looks along +z).
  for (std::size_t i = 0; i < normal.rgb.size(); i += 3)
    ASSERT_LE(std::hypot(normal.rgb[i], normal.rgb[i + 1], normal.rgb[i + 2]), 1.0 + 1e-5) << "pixel " << i / 3;
  const float* middle = normal.pixel(16, 12);
  EXPECT_NEAR(middle[2], -1.0, 1e-5) << middle[0] << ", " << middle[1];
}

TEST(Denoise, TheDenoisedImageIsTheMainLayerAndFarCloserToTheReferenceThanTheRawOne) {
  REQUIRE_DENOISER();
  const std::string dir = fresh_dir("denoise");
  const std::string common = "render " + kCornell + " --width 64 --height 64 --mode pt --seed 3 ";
  CliResult d = run_cli(common + "--spp 4 --denoise --out " + dir + "/d --stats " + dir + "/d.json");
  ASSERT_EQ(d.exit_code, 0) << d.output;
  EXPECT_NE(d.output.find("denoised by OpenImageDenoise"), std::string::npos) << d.output;
  EXPECT_NE(d.output.find("of the raw image"), std::string::npos) << d.output;
  CliResult raw = run_cli(common + "--spp 4 --out " + dir + "/r");
  ASSERT_EQ(raw.exit_code, 0) << raw.output;
  CliResult ref = run_cli("render " + kCornell + " --width 64 --height 64 --mode pt --seed 11 --spp 1024 --out " +
                          dir + "/ref");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  // The raw layer is the render without --denoise, bit for bit: the denoiser only reads it.
  EXPECT_EQ(read_exr(dir + "/d.exr", "raw").rgb, read_exr(dir + "/r.exr").rgb);
  const ImageRGB reference = read_exr(dir + "/ref.exr");
  const double raw_error = compare_images(read_exr(dir + "/r.exr"), reference).rel_mse;
  const double denoised_error = compare_images(read_exr(dir + "/d.exr"), reference).rel_mse;
  // At 4 spp OIDN removes most of the noise (measured: about a tenth is left); the reference's own
  // noise is 1/256 of the raw image's.
  EXPECT_LT(denoised_error, 0.3 * raw_error) << "raw " << raw_error << ", denoised " << denoised_error;
  nlohmann::json stats = nlohmann::json::parse(std::ifstream(dir + "/d.json"));
  EXPECT_EQ(stats["denoised"], true);
  EXPECT_GE(stats["denoiser"]["version"].get<int>(), 20000);
}

}  // namespace
}  // namespace bp::test

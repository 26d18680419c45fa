// Several devices in one render (docs/design.md §8), on PoCL's two CPU devices of one machine: equal ones
// (POCL_DEVICES="pthread pthread") and unequal ones ("basic pthread": one thread against all). The
// variable is set for the bundlepath process, before it first asks for an OpenCL platform.
#include "e2e/cli_runner.h"
#include "image/image.h"
#include "kernel/region_test.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace bp::test {
namespace {

namespace fs = std::filesystem;
const std::string kCornell = std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf ";
const std::string kEqualDevices = "POCL_DEVICES='pthread pthread'";
const std::string kUnequalDevices = "POCL_DEVICES='basic pthread'";  // [0] one thread, [1] all

nlohmann::json read_stats(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

// Large-region means of two images agree to float summation order.
void expect_same_regions(const ImageRGB& a, const ImageRGB& b, double relative) {
  const std::vector<double> ra = large_region_means(a), rb = large_region_means(b);
  for (int i = 0; i < kLargeRegions; ++i)
    EXPECT_NEAR(ra[i], rb[i], relative * std::abs(rb[i])) << large_region_name(i);
}

TEST(Devices, BadDeviceListsExitTwoNamingTheOption) {
  const std::string dir = fresh_dir("devices_bad");
  for (const std::string spec : {"0,,1", "0,0", "all,1", ",0"}) {
    CliResult r = run_cli("render " + kCornell + "--width 8 --spp 1 --out " + dir + "/x --device " + spec, kEqualDevices);
    EXPECT_EQ(r.exit_code, 2) << spec << "\n" << r.output;
    EXPECT_NE(r.output.find("--device '" + spec + "'"), std::string::npos) << r.output;
  }
  // An item that names no device is a device error (exit 1, as for one device), listing them.
  CliResult r = run_cli("render " + kCornell + "--width 8 --spp 1 --out " + dir + "/x --device 0,no-such-xyz",
                        kEqualDevices);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("[1] "), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/x.exr"));
}

// PT on one device and RB on the other, at the same time: per-region z-tests against one device over
// independent seeds, and the same seed gives the one-device image (the same samples and chain).
TEST(Devices, TwoDeviceCombinedRenderAgreesWithOneDevice) {
  const std::string dir = fresh_dir("devices_combined");
  const std::string common = "render " + kCornell + "--width 24 --height 24 --mode combined --ratio 1 --spp 16 ";
  auto render = [&](const std::string& devices, std::uint32_t seed) {
    const std::string out = dir + "/d" + devices + "_" + std::to_string(seed);
    CliResult r = run_cli(common + "--device " + devices + " --seed " + std::to_string(seed) + " --out " + out +
                              " --stats " + out + ".json",
                          kEqualDevices);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return read_exr(out + ".exr");
  };
  const int runs = 4;
  const RegionRuns one = large_region_runs(runs, 11, [&](std::uint32_t seed) { return render("0", seed); });
  const RegionRuns two = large_region_runs(runs, 11, [&](std::uint32_t seed) { return render("0,1", seed); });
  const double alpha = sidak_alpha(0.01, kLargeRegions);
  for (int i = 0; i < kLargeRegions; ++i) {
    const WelchT w = welch_t(two, one, i);
    EXPECT_GT(student_t_two_sided_p(w.t, w.dof), alpha) << large_region_name(i) << ": " << two.mean[i] << " vs "
                                                        << one.mean[i] << " (t " << w.t << ")";
  }
  expect_same_regions(read_exr(dir + "/d0,1_11.exr"), read_exr(dir + "/d0_11.exr"), 1e-5);

  const nlohmann::json stats = read_stats(dir + "/d0,1_11.json");
  ASSERT_EQ(stats["devices"].size(), 2u) << stats.dump();
  EXPECT_EQ(stats["devices"][0]["rb_iterations"], 16);  // RB on the first device, PT on the other
  EXPECT_EQ(stats["devices"][1]["pt_samples"], 16);
  for (const auto& d : stats["devices"]) EXPECT_GT(d["busy_seconds"].get<double>(), 0.0) << d.dump();
  const nlohmann::json single = read_stats(dir + "/d0_11.json");
  ASSERT_EQ(single["devices"].size(), 1u);
  EXPECT_EQ(single["devices"][0]["pt_samples"], 16);
  EXPECT_EQ(single["devices"][0]["rb_iterations"], 16);
}

// PT split by sample index in proportion to measured speed: the slower device takes fewer samples,
// and the image is the one-device image of the same samples. Two PoCL devices share this machine's
// cores, so with others running "basic" (one thread) is about as fast as "pthread": the test hook
// makes it three times slower as well.
TEST(Devices, SlowerDeviceTakesFewerPathTracingSamples) {
  const std::string dir = fresh_dir("devices_unequal");
  const std::string common = "render " + kCornell + "--mode pt --width 32 --height 32 --spp 64 ";
  CliResult r = run_cli(common + "--device all --out " + dir + "/two --stats " + dir + "/two.json",
                        kUnequalDevices + " BUNDLEPATH_TEST_SLOW_DEVICE=0:3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(run_cli(common + "--device 1 --out " + dir + "/one", kUnequalDevices).exit_code, 0);
  const nlohmann::json stats = read_stats(dir + "/two.json");
  ASSERT_EQ(stats["devices"].size(), 2u) << stats.dump();
  const std::uint64_t basic = stats["devices"][0]["pt_samples"], pthread = stats["devices"][1]["pt_samples"];
  EXPECT_GT(basic, 0u) << stats["devices"].dump();
  EXPECT_LT(basic, pthread) << stats["devices"].dump();
  EXPECT_EQ(basic + pthread, 64u);
  expect_same_regions(read_exr(dir + "/two.exr"), read_exr(dir + "/one.exr"), 1e-5);
}

// --ratio auto on two devices picks the round that keeps both busy, and both do work.
TEST(Devices, AutoRatioOnTwoDevicesKeepsBothBusy) {
  const std::string dir = fresh_dir("devices_auto");
  CliResult r = run_cli("render " + kCornell + "--width 24 --height 24 --mode combined --spp 8 --device all --out " +
                            dir + "/auto --stats " + dir + "/auto.json",
                        kUnequalDevices);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("keeps both busy"), std::string::npos) << r.output;
  const nlohmann::json stats = read_stats(dir + "/auto.json");
  EXPECT_EQ(stats["ratio_auto"]["rule"], "concurrent") << stats.dump();
  EXPECT_GT(stats["devices"][0]["rb_iterations"].get<std::uint64_t>(), 0u) << stats.dump();
  EXPECT_GE(stats["devices"][1]["pt_samples"].get<std::uint64_t>(), 8u) << stats.dump();
}

// A device that fails mid-render ends it with the rounds completed before: exit 1, a message naming
// the device, and the image that a render of those rounds alone gives.
TEST(Devices, FailingDeviceLeavesThePartialImage) {
  const std::string dir = fresh_dir("devices_failure");
  const std::string common = "render " + kCornell + "--width 24 --height 24 --mode combined --ratio 1 ";
  // Batches of 1, 1, 2, 4 rounds: failing in the fourth leaves 4.
  CliResult r = run_cli(common + "--spp 64 --device 0,1 --out " + dir + "/partial --stats " + dir + "/partial.json",
                        kEqualDevices + " BUNDLEPATH_TEST_FAIL_DEVICE=1:3");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("device [1] pthread"), std::string::npos) << r.output;
  ASSERT_TRUE(fs::exists(dir + "/partial.exr")) << r.output;
  const nlohmann::json stats = read_stats(dir + "/partial.json");
  EXPECT_EQ(stats["spp"], 4) << stats.dump();
  EXPECT_NE(stats["device_failure"].get<std::string>().find("device [1]"), std::string::npos);
  ASSERT_EQ(run_cli(common + "--spp 4 --device 0 --out " + dir + "/four", kEqualDevices).exit_code, 0);
  const ImageRGB partial = read_exr(dir + "/partial.exr");
  for (float v : partial.rgb) ASSERT_TRUE(std::isfinite(v));
  expect_same_regions(partial, read_exr(dir + "/four.exr"), 1e-5);
}

// Checkpoints on two devices: stopped and resumed equals the render that ran through (to float
// summation order: the PT split follows measured speed).
TEST(Devices, StoppedAndResumedOnTwoDevicesEqualsUninterrupted) {
  const std::string dir = fresh_dir("devices_checkpoint");
  const std::string common = "render " + kCornell + "--width 24 --height 18 --mode combined --ratio 1 --device 0,1 ";
  ASSERT_EQ(run_cli(common + "--spp 24 --out " + dir + "/whole", kEqualDevices).exit_code, 0);
  ASSERT_EQ(run_cli(common + "--spp 8 --checkpoint " + dir + "/ck --out " + dir + "/first", kEqualDevices).exit_code, 0);
  CliResult r = run_cli(common + "--spp 24 --resume " + dir + "/ck --out " + dir + "/rest", kEqualDevices);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const std::string layer : {"", "pt", "rb"})
    expect_same_regions(read_exr(dir + "/rest.exr", layer), read_exr(dir + "/whole.exr", layer), 1e-5);
}

// Ctrl-C on two devices: both finish the batch they are in, and the image of the rounds done is written.
TEST(Devices, SigintOnTwoDevicesWritesTheRoundsDoneAndExits130) {
  const std::string dir = fresh_dir("devices_sigint");
  const std::string render = kEqualDevices + " '" + std::string(BP_BINARY) + "' render " + kCornell +
                             "--width 32 --height 32 --mode combined --ratio 1 --spp 100000000 --device 0,1 --out " +
                             dir + "/i --stats " + dir + "/s.json";
  CliResult r = interrupt_once_started(render, dir);
  EXPECT_NE(r.output.find("exit=130"), std::string::npos) << r.output;
  const nlohmann::json stats = read_stats(dir + "/s.json");
  EXPECT_TRUE(stats["interrupted"].get<bool>());
  const std::uint64_t rounds = stats["rounds"];
  EXPECT_GE(rounds, 1u);
  EXPECT_EQ(stats["devices"][0]["rb_iterations"], rounds) << stats.dump();
  EXPECT_EQ(stats["devices"][1]["pt_samples"], rounds) << stats.dump();
  const ImageRGB img = read_exr(dir + "/i.exr");
  double sum = 0;
  for (float v : img.rgb) sum += v;
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace bp::test

// --checkpoint / --resume: a render stopped anywhere (a count reached, or Ctrl-C) and resumed gives the
// same image, bit for bit, as one that ran through; a checkpoint from other options is refused.
#include "e2e/cli_runner.h"
#include "image/image.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace bp::test {
namespace {

namespace fs = std::filesystem;
const std::string kGlossy = std::string(BP_SOURCE_DIR) + "/scenes/cornell-glossy.gltf ";

void expect_same_image(const std::string& a, const std::string& b) {
  for (const std::string& layer : exr_layer_names(a)) {
    ImageRGB x = read_exr(a, layer), y = read_exr(b, layer);
    ASSERT_EQ(x.rgb.size(), y.rgb.size());
    EXPECT_EQ(x.rgb, y.rgb) << "layer '" << layer << "' differs";
  }
}

TEST(Checkpoint, StoppedAndResumedEqualsUninterruptedInEveryMode) {
  std::string dir = fresh_dir("checkpoint_modes");
  const std::string common = "render " + kGlossy + "--width 24 --height 18 --layers all ";
  for (const std::string mode : {"--mode pt --spp", "--mode rb --iterations", "--mode combined --ratio 1/4 --spp"}) {
    ASSERT_EQ(run_cli(common + mode + " 24 --out " + dir + "/whole").exit_code, 0) << mode;
    ASSERT_EQ(run_cli(common + mode + " 8 --checkpoint " + dir + "/ck --out " + dir + "/first").exit_code, 0) << mode;
    CliResult r = run_cli(common + mode + " 24 --resume " + dir + "/ck --stats " + dir + "/s.json --out " + dir + "/rest");
    ASSERT_EQ(r.exit_code, 0) << mode << "\n" << r.output;
    expect_same_image(dir + "/rest.exr", dir + "/whole.exr");
    nlohmann::json stats = nlohmann::json::parse(std::ifstream(dir + "/s.json"));
    EXPECT_EQ(stats["resumed_from_rounds"], 8) << mode;
  }
}

TEST(Checkpoint, CtrlCThenResumeEqualsUninterrupted) {
  std::string dir = fresh_dir("checkpoint_sigint");
  const std::string render = "'" + std::string(BP_BINARY) + "' render " + kGlossy + "--mode combined --ratio 1/4 --width 96 " +
                             "--height 96 --spp 256 ";
  ASSERT_EQ(run_shell(render + "--out " + dir + "/whole").exit_code, 0);
  // Interrupted once it has started, at whatever batch it has reached; the checkpoint is written on the way out.
  // The renderer itself is signalled, once (see Cli.SigintWritesTheSamplesDoneAndExits130); a watchdog bounds it.
  CliResult r = run_shell(render + "--checkpoint " + dir + "/ck --out " + dir + "/cut 2>" + dir + "/log & pid=$!; " +
                          "(sleep 300; kill -KILL $pid) >/dev/null 2>&1 & watchdog=$!; for i in $(seq 600); do grep -q " +
                          "rendering " + dir + "/log && break; sleep 0.1; done; sleep 0.5; kill -INT $pid; " +
                          "wait $pid; echo \"exit=$?\"; kill $watchdog 2>/dev/null");
  ASSERT_NE(r.output.find("exit=130"), std::string::npos) << r.output;
  r = run_shell(render + "--resume " + dir + "/ck --out " + dir + "/resumed");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_image(dir + "/resumed.exr", dir + "/whole.exr");
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos);
}

// --ratio auto probes once: the resumed run takes the checkpoint's c (no probe), and the image is the
// uninterrupted render at that c.
TEST(Checkpoint, ResumedAutoRatioReusesTheSavedRatio) {
  std::string dir = fresh_dir("checkpoint_auto_ratio");
  // 128x96: a PT sample costs more than an RB iteration, so c is finite (the path tracer alone: below).
  const std::string common = "render " + kGlossy + "--width 128 --height 96 --mode combined ";
  CliResult first = run_cli(common + "--ratio auto --spp 8 --checkpoint " + dir + "/ck --stats " + dir + "/first.json --out " +
                            dir + "/first");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  nlohmann::json s1 = nlohmann::json::parse(std::ifstream(dir + "/first.json"));
  const double chosen = s1["ratio_auto"]["chosen"].get<double>();
  CliResult rest = run_cli(common + "--ratio auto --spp 64 --resume " + dir + "/ck --stats " + dir + "/rest.json --out " +
                           dir + "/rest");
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  EXPECT_EQ(rest.output.find("--ratio auto: c ="), std::string::npos) << "a resumed render must not probe again";
  nlohmann::json s2 = nlohmann::json::parse(std::ifstream(dir + "/rest.json"));
  EXPECT_EQ(s2["ratio"].get<double>(), chosen);
  EXPECT_EQ(s2["ratio_auto"]["from_checkpoint"], true);
  // --eye-direct auto, the same: 8 spp shared the eye vertex's direct light, and the resumed render
  // keeps that although 64 spp alone would give it to PT.
  EXPECT_EQ(s1["eye_direct"], "shared");
  EXPECT_EQ(s2["eye_direct"], "shared");
  EXPECT_EQ(rest.output.find("--eye-direct auto:"), std::string::npos) << "a resumed render must not choose again";
  const std::string fixed = chosen >= 1.0 ? std::to_string(std::lround(chosen)) : "1/" + std::to_string(std::lround(1.0 / chosen));
  ASSERT_EQ(run_cli(common + "--ratio " + fixed + " --eye-direct shared --spp 64 --out " + dir + "/whole").exit_code, 0);
  expect_same_image(dir + "/rest.exr", dir + "/whole.exr");
}

// Where --ratio auto chose the path tracer alone (a tiny image), the resumed render does too: the
// image of --mode pt, bit for bit; counted in RB iterations it is refused.
TEST(Checkpoint, ResumedPathTracerAloneStaysAlone) {
  std::string dir = fresh_dir("checkpoint_pt_alone");
  const std::string common = "render " + kGlossy + "--width 4 --height 4 ";
  CliResult first = run_cli(common + "--mode combined --spp 8 --checkpoint " + dir + "/ck --out " + dir + "/first");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  ASSERT_NE(first.output.find("the path tracer alone"), std::string::npos) << first.output;
  CliResult rest = run_cli(common + "--mode combined --spp 16 --resume " + dir + "/ck --out " + dir + "/rest");
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  ASSERT_EQ(run_cli(common + "--mode pt --spp 16 --out " + dir + "/whole").exit_code, 0);
  EXPECT_EQ(read_exr(dir + "/rest.exr").rgb, read_exr(dir + "/whole.exr").rgb);
  CliResult counted = run_cli(common + "--mode combined --iterations 16 --resume " + dir + "/ck --out " + dir + "/it");
  EXPECT_EQ(counted.exit_code, 2) << counted.output;
  EXPECT_NE(counted.output.find("not --iterations"), std::string::npos) << counted.output;
}

TEST(Checkpoint, OtherOptionsOrABrokenFileAreRefused) {
  std::string dir = fresh_dir("checkpoint_refused");
  const std::string base = "render " + kGlossy + "--mode pt --width 16 --height 16 ";
  ASSERT_EQ(run_cli(base + "--spp 4 --checkpoint " + dir + "/ck --out " + dir + "/a").exit_code, 0);
  CliResult r = run_cli(base + "--spp 8 --seed 9 --resume " + dir + "/ck --out " + dir + "/b");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("seed=9"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/b.exr"));
  std::ofstream(dir + "/junk") << "not a checkpoint";
  r = run_cli(base + "--spp 8 --resume " + dir + "/junk --out " + dir + "/c");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("not a bundlepath checkpoint"), std::string::npos) << r.output;
  fs::resize_file(dir + "/ck", fs::file_size(dir + "/ck") / 2);
  r = run_cli(base + "--spp 8 --resume " + dir + "/ck --out " + dir + "/d");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("truncated"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bp::test

// Walkthroughs (issue #15, docs/design.md §8): every view source, the frames of one shared ray-bundle
// chain against single-view renders, and the bad inputs.
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
// scenes/cornell-box.gltf with camera nodes 0 "camera", 1 "left", 2 "walker" (animated; make_walk_scene.py).
const std::string kWalk = std::string(BP_SOURCE_DIR) + "/tests/data/gltf/good/cornell-walk.gltf";
const std::string kSmall = " --width 48 --height 48 --seed 7 --warmup 4 ";

std::string frame(const std::string& prefix, int k) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "_%04d", k);
  return prefix + buf + ".exr";
}

// The largest difference of any pixel channel relative to the image's mean level (0: bit-identical).
double max_relative_difference(const ImageRGB& a, const ImageRGB& b) {
  EXPECT_EQ(a.rgb.size(), b.rgb.size());
  double mean = 0.0, worst = 0.0;
  for (float v : b.rgb) mean += v;
  mean /= double(b.rgb.size());
  for (std::size_t i = 0; i < a.rgb.size() && i < b.rgb.size(); ++i)
    worst = std::max(worst, std::abs(double(a.rgb[i]) - double(b.rgb[i])) / mean);
  return worst;
}

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

// Frame k of --cameras all equals the single render of --camera k (same seed, options and counts):
// the views share RB's chain and each has its own eye gather and PT samples. The frames differ from
// each other, so the equality is not that of one view written three times.
void expect_frames_equal_single_renders(const std::string& name, const std::string& mode_and_counts) {
  const std::string dir = fresh_dir("walk-" + name);
  CliResult all = run_cli("render " + kWalk + kSmall + mode_and_counts + " --cameras all --out " + dir + "/all --stats " +
                          dir + "/all.json");
  ASSERT_EQ(all.exit_code, 0) << all.output;
  const nlohmann::json stats = read_json(dir + "/all.json");
  ASSERT_EQ(stats["frames"].size(), 3u);
  std::vector<ImageRGB> frames;
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(stats["frames"][k]["exr"], frame(dir + "/all", k));
    EXPECT_TRUE(fs::exists(dir + "/all_000" + std::to_string(k) + ".png"));
    frames.push_back(read_exr(frame(dir + "/all", k)));
    CliResult one = run_cli("render " + kWalk + kSmall + mode_and_counts + " --camera " + std::to_string(k) +
                            " --out " + dir + "/one" + std::to_string(k));
    ASSERT_EQ(one.exit_code, 0) << one.output;
    EXPECT_LE(max_relative_difference(frames[k], read_exr(dir + "/one" + std::to_string(k) + ".exr")), 1e-6)
        << name << " frame " << k;
  }
  EXPECT_GT(max_relative_difference(frames[0], frames[1]), 0.01) << "the views see different images";
  EXPECT_GT(max_relative_difference(frames[1], frames[2]), 0.01) << "the views see different images";
}

TEST(Walkthrough, RayBundleFramesEqualSingleCameraRenders) {
  expect_frames_equal_single_renders("rb", "--mode rb --iterations 12");
}

TEST(Walkthrough, PathTracerFramesEqualSingleCameraRenders) {
  expect_frames_equal_single_renders("pt", "--mode pt --spp 4");
}

TEST(Walkthrough, CombinedFramesEqualSingleCameraRenders) {
  expect_frames_equal_single_renders("combined", "--mode combined --ratio 1/2 --iterations 8");
}

// One view: PREFIX.exr as before; the default view is camera node 0, and a node's name picks it as
// its index does.
TEST(Walkthrough, CameraByIndexNameAndDefault) {
  const std::string dir = fresh_dir("walk-camera");
  const std::string common = "render " + kWalk + kSmall + " --mode pt --spp 2 --out " + dir;
  ASSERT_EQ(run_cli(common + "/default").exit_code, 0);
  ASSERT_EQ(run_cli(common + "/zero --camera 0").exit_code, 0);
  ASSERT_EQ(run_cli(common + "/two --camera 2").exit_code, 0);
  ASSERT_EQ(run_cli(common + "/walker --camera walker").exit_code, 0);
  EXPECT_FALSE(fs::exists(dir + "/default_0000.exr"));
  EXPECT_EQ(max_relative_difference(read_exr(dir + "/default.exr"), read_exr(dir + "/zero.exr")), 0.0);
  EXPECT_EQ(max_relative_difference(read_exr(dir + "/two.exr"), read_exr(dir + "/walker.exr")), 0.0);
  EXPECT_GT(max_relative_difference(read_exr(dir + "/zero.exr"), read_exr(dir + "/two.exr")), 0.01);
}

// A camera path file: one frame per key, at the key's position, looking at its target.
TEST(Walkthrough, CameraPathFileGivesOneFramePerKey) {
  const std::string dir = fresh_dir("walk-path");
  std::ofstream(dir + "/path.json") << R"([
    {"position": [0.278, 0.273, -0.8], "target": [0.278, 0.273, 0.0], "up": [0, 1, 0], "yfov": 0.6860478808414068},
    {"position": [0.1, 0.3, -0.5], "target": [0.4, 0.2, 0.3], "yfov": 0.9}
  ])";
  CliResult r = run_cli("render " + kWalk + kSmall + "--mode pt --spp 2 --camera-path " + dir + "/path.json --out " +
                        dir + "/p --stats " + dir + "/p.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json frames = read_json(dir + "/p.json")["frames"];
  ASSERT_EQ(frames.size(), 2u);
  const double expected_forward[2][3] = {{0, 0, 1}, {0.3 / std::sqrt(0.74), -0.1 / std::sqrt(0.74), 0.8 / std::sqrt(0.74)}};
  const double expected_position[2][3] = {{0.278, 0.273, -0.8}, {0.1, 0.3, -0.5}};
  for (int k = 0; k < 2; ++k)
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(frames[k]["position"][c].get<double>(), expected_position[k][c], 1e-6) << k;
      EXPECT_NEAR(frames[k]["forward"][c].get<double>(), expected_forward[k][c], 1e-6) << k;
    }
  EXPECT_NEAR(frames[1]["yfov"].get<double>(), 0.9, 1e-6);
  EXPECT_TRUE(fs::exists(dir + "/p_0001.png"));
  // Key 0 is camera node 0's view: its frame is that render's image (up to float rounding of the axes).
  ASSERT_EQ(run_cli("render " + kWalk + kSmall + "--mode pt --spp 2 --out " + dir + "/zero").exit_code, 0);
  EXPECT_LE(max_relative_difference(read_exr(dir + "/p_0000.exr"), read_exr(dir + "/zero.exr")), 1e-6);
}

// "walker" (a child of "rig", +0.1 in x) moves LINEARly from z = -0.8 at t = 0 to -0.4 at t = 1 and
// turns by STEP from 180 to 160 degrees about y at t = 0.5: at 4 fps, frames at t = 0, 0.25, ... 1.
TEST(Walkthrough, AnimatedCameraIsSampledLinearAndStep) {
  const std::string dir = fresh_dir("walk-animation");
  CliResult r = run_cli("render " + kWalk + " --width 16 --height 16 --mode pt --spp 1 --camera walker "
                        "--camera-animation --fps 4 --out " + dir + "/a --stats " + dir + "/a.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json frames = read_json(dir + "/a.json")["frames"];
  ASSERT_EQ(frames.size(), 5u);
  const double turned = 160.0 * M_PI / 180.0;
  for (int k = 0; k < 5; ++k) {
    const double t = 0.25 * k;
    EXPECT_NEAR(frames[k]["position"][0].get<double>(), 0.278, 1e-6) << "the parent's +0.1";
    EXPECT_NEAR(frames[k]["position"][1].get<double>(), 0.273, 1e-6);
    EXPECT_NEAR(frames[k]["position"][2].get<double>(), -0.8 + 0.4 * t, 1e-6) << "LINEAR at t = " << t;
    const double fx = t < 0.5 ? 0.0 : -std::sin(turned), fz = t < 0.5 ? 1.0 : -std::cos(turned);
    EXPECT_NEAR(frames[k]["forward"][0].get<double>(), fx, 1e-6) << "STEP at t = " << t;
    EXPECT_NEAR(frames[k]["forward"][2].get<double>(), fz, 1e-6) << "STEP at t = " << t;
    EXPECT_TRUE(fs::exists(frame(dir + "/a", k)));
  }
  // 3 fps: t = 0, 1/3, 2/3, 1.
  ASSERT_EQ(run_cli("render " + kWalk + " --width 8 --height 8 --mode pt --spp 1 --camera 2 --camera-animation "
                    "--fps 3 --out " + dir + "/b --stats " + dir + "/b.json").exit_code, 0);
  EXPECT_EQ(read_json(dir + "/b.json")["frames"].size(), 4u);
}

TEST(Walkthrough, BadViewInputsExitWithOneLine) {
  const std::string dir = fresh_dir("walk-bad");
  std::ofstream(dir + "/empty.json") << "[]";
  std::ofstream(dir + "/broken.json") << "[{\"position\": [0, 0, 0], ";
  std::ofstream(dir + "/no-target.json") << R"([{"position": [0, 0, 0]}])";
  std::ofstream(dir + "/same.json") << R"([{"position": [1, 2, 3], "target": [1, 2, 3]}])";
  std::ofstream(dir + "/fov.json") << R"([{"position": [0, 0, 0], "target": [0, 0, 1], "yfov": 4}])";
  struct Case {
    std::string args;
    int exit_code;
    std::string needle;
  };
  const Case cases[] = {
      {"--camera 7", 2, "no such camera"},
      {"--camera nosuch", 2, "no camera node or camera of that name"},
      {"--camera light", 2, "holds no perspective camera"},
      {"--cameras every", 2, "--cameras"},
      {"--cameras all --camera 1", 2, "one view source"},
      {"--camera left --camera-animation", 2, "not animated"},
      {"--camera 2 --camera-animation --fps 0", 2, "--fps"},
      {"--camera 2 --camera-animation --fps -24", 2, "--fps"},
      {"--camera-path " + dir + "/empty.json", 3, "empty"},
      {"--camera-path " + dir + "/broken.json", 3, "not JSON"},
      {"--camera-path " + dir + "/no-target.json", 3, "key 0"},
      {"--camera-path " + dir + "/same.json", 3, "target at its position"},
      {"--camera-path " + dir + "/fov.json", 3, "yfov"},
      {"--camera-path " + dir + "/missing.json", 3, "cannot open"},
      {"--cameras all --reference " + dir + "/r.exr", 2, "--reference"},
      {"--video " + dir + "/v.mp4", 2, "--video encodes a walkthrough"},
  };
  for (const Case& c : cases) {
    CliResult r = run_cli("render " + kWalk + " --width 8 --mode pt --spp 1 --out " + dir + "/x " + c.args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << c.args << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(dir + "/x.exr"));
  EXPECT_FALSE(fs::exists(dir + "/x_0000.exr"));
  // A scene without camera nodes has no camera to pick.
  CliResult r = run_cli("render " + std::string(BP_SOURCE_DIR) + "/tests/data/gltf/good/triangle.glb --width 8 "
                        "--spp 1 --out " + dir + "/y --cameras all");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no perspective camera node"), std::string::npos) << r.output;
}

// A walk stopped at a checkpoint and resumed gives every frame of the walk that ran through, bit for
// bit (the one chain's state and each view's accumulators and error estimate are saved); a checkpoint
// of other views is refused.
TEST(Walkthrough, CheckpointedWalkResumesToTheUninterruptedFrames) {
  const std::string dir = fresh_dir("walk-checkpoint");
  const std::string common = "render " + kWalk + " --width 24 --height 24 --warmup 4 --mode combined --ratio 1/2 "
                             "--cameras all --iterations ";
  ASSERT_EQ(run_cli(common + "16 --out " + dir + "/whole").exit_code, 0);
  ASSERT_EQ(run_cli(common + "8 --checkpoint " + dir + "/ck --out " + dir + "/first").exit_code, 0);
  CliResult r = run_cli(common + "16 --resume " + dir + "/ck --stats " + dir + "/s.json --out " + dir + "/rest");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_json(dir + "/s.json")["resumed_from_rounds"], 4);
  for (int k = 0; k < 3; ++k)
    for (const std::string layer : {"", "pt", "rb", "stderr"}) {
      const ImageRGB rest = read_exr(frame(dir + "/rest", k), layer), whole = read_exr(frame(dir + "/whole", k), layer);
      EXPECT_EQ(rest.rgb, whole.rgb) << "frame " << k << " layer '" << layer << "'";
    }
  EXPECT_GT(max_relative_difference(read_exr(frame(dir + "/rest", 0)), read_exr(frame(dir + "/first", 0))), 0.0)
      << "the resumed walk went on from the checkpoint";
  // The same checkpoint under other views: refused with both keys.
  std::ofstream(dir + "/path.json") << R"([{"position": [0.278, 0.273, -0.8], "target": [0.278, 0.273, 0]}])";
  r = run_cli("render " + kWalk + " --width 24 --height 24 --warmup 4 --mode combined --ratio 1/2 --iterations 16 "
              "--camera-path " + dir + "/path.json --resume " + dir + "/ck --out " + dir + "/other");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("saved with other options"), std::string::npos) << r.output;
}

// A CUBICSPLINE camera animation fails only the render that plays it; the scene renders otherwise.
TEST(Walkthrough, UnplayableAnimationFailsOnlyTheRenderThatPlaysIt) {
  const std::string dir = fresh_dir("walk-cubic");
  std::ifstream in(kWalk);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t step = text.find("\"STEP\"");
  ASSERT_NE(step, std::string::npos);
  text.replace(step, 6, "\"CUBICSPLINE\"");
  std::ofstream(dir + "/cubic.gltf") << text;
  const std::string common = "render " + dir + "/cubic.gltf --width 8 --mode pt --spp 1 --camera 2 --out " + dir;
  EXPECT_EQ(run_cli(common + "/still").exit_code, 0);
  CliResult r = run_cli(common + "/played --camera-animation");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("interpolation CUBICSPLINE"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/played_0000.exr"));
}

// --video needs ffmpeg: without it on PATH, one line naming the package, before anything is rendered.
TEST(Walkthrough, VideoWithoutFfmpegIsRefused) {
  const std::string dir = fresh_dir("walk-video");
  CliResult r = run_cli("render " + kWalk + " --width 8 --mode pt --spp 1 --cameras all --video " + dir +
                            "/v.mp4 --out " + dir + "/v",
                        "PATH=/nonexistent");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--video needs ffmpeg"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/v_0000.exr"));
}

// --video: ffmpeg encodes every frame's PNG at --fps (9 frames: the walker's second at 8 fps).
TEST(Walkthrough, VideoEncodesEveryFrame) {
  if (run_shell("command -v ffmpeg && command -v ffprobe").exit_code != 0)
    GTEST_SKIP() << "ffmpeg is not installed (scripts/test.sh installs it)";
  const std::string dir = fresh_dir("walk-video-encoded");
  CliResult r = run_cli("render " + kWalk + " --width 24 --height 24 --mode rb --iterations 4 --warmup 2 --camera 2 "
                        "--camera-animation --fps 8 --out " + dir + "/a --video " + dir + "/a.mp4 --stats " + dir +
                        "/a.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_json(dir + "/a.json")["video"], dir + "/a.mp4");
  CliResult probe = run_shell("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                              "stream=nb_read_frames,r_frame_rate,width -of csv=p=0 " + dir + "/a.mp4");
  ASSERT_EQ(probe.exit_code, 0) << probe.output;
  EXPECT_EQ(probe.output, "24,8/1,9\n");
}

// Memory grows with the views: a walk that cannot fit is refused naming the size and the views.
TEST(Walkthrough, WalkThatCannotFitIsRefusedNamingSizeAndViews) {
  const std::string dir = fresh_dir("walk-memory");
  CliResult r = run_cli("render " + kWalk + " --width 16384 --height 16384 --mode pt --spp 1 --cameras all --out " +
                        dir + "/m");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("3 view(s) of 16384x16384"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lower --width/--height or the number of views"), std::string::npos) << r.output;
}

// Ctrl-C writes every frame of the rounds done.
TEST(Walkthrough, SigintWritesEveryFrame) {
  const std::string dir = fresh_dir("walk-sigint");
  const std::string render = std::string("'") + BP_BINARY + "' render " + kWalk +
                             " --width 32 --height 32 --mode rb --iterations 100000000 --cameras all --out " + dir +
                             "/i --stats " + dir + "/s.json";
  CliResult r = interrupt_once_started(render, dir);
  EXPECT_NE(r.output.find("exit=130"), std::string::npos) << r.output;
  const nlohmann::json stats = read_json(dir + "/s.json");
  EXPECT_TRUE(stats["interrupted"].get<bool>());
  ASSERT_EQ(stats["frames"].size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const ImageRGB img = read_exr(frame(dir + "/i", k));
    double sum = 0;
    for (float v : img.rgb) sum += v;
    EXPECT_GT(sum, 0.0) << "frame " << k << " holds the iterations done";
  }
}

}  // namespace
}  // namespace bp::test

// One render on two MPI ranks (docs/design.md §8) against one process, through `mpirun -np 2` and the
// real binary. Built only where CMake found MPI and Open MPI's mpirun (BP_MPIRUN). The flags keep
// mpirun working in a CI container: as root, two ranks whatever the core count, and shared memory
// between the ranks without the network or ptrace (CMA) that a container may lack. Under
// scripts/test-sanitizers.sh the ranks unwind malloc stacks fully, so that tests/sanitizers/lsan.supp
// can name the Open MPI libraries whose objects outlive MPI_Finalize (they have no frame pointers).
#ifdef BP_MPIRUN
#include "e2e/cli_runner.h"
#include "image/image.h"
#include "kernel/region_test.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace bp::test {
namespace {

namespace fs = std::filesystem;
const std::string kCornell = std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf ";
// timeout --foreground: without it timeout signals its whole process group, so a SIGINT sent to it
// reached mpirun twice (itself and the group), and a second SIGINT makes mpirun kill the ranks at once.
const std::string kTwoRanks = std::string("ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}fast_unwind_on_malloc=0\" ") +
                              "timeout --foreground 300 " + BP_MPIRUN +
                              " --oversubscribe --allow-run-as-root --mca pml ob1 --mca btl self,vader"
                              " --mca btl_vader_single_copy_mechanism none -np 2 ";

nlohmann::json read_stats(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

CliResult run_on_two_ranks(const std::string& args) {
  return run_shell(kTwoRanks + "'" + BP_BINARY + "' " + args);
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Independent renders of one process and of two ranks (other seeds: the same seed would share PT's
// samples) agree in the image mean and its quadrants (Welch t-tests at a Šidák-corrected 1 %); RB runs
// a chain of its own on each rank. Power: the image mean's difference is known to within 3 % of it,
// so a bias of about 10 % (a lost or doubled part of a rank's sums is 50 %) would show.
void expect_regions_agree(const std::string& options, int runs, const std::string& dir) {
  auto render = [&](bool two_ranks, std::uint32_t seed) {
    const std::string out = dir + (two_ranks ? "/two_" : "/one_") + std::to_string(seed);
    const std::string args = "render " + kCornell + options + " --seed " + std::to_string(seed) + " --out " + out;
    const CliResult r = two_ranks ? run_on_two_ranks(args) : run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return read_exr(out + ".exr");
  };
  const RegionRuns one = large_region_runs(runs, 5, [&](std::uint32_t seed) { return render(false, seed); });
  const RegionRuns two = large_region_runs(runs, 5005, [&](std::uint32_t seed) { return render(true, seed); });
  const double alpha = sidak_alpha(0.01, kLargeRegions);
  EXPECT_LT(welch_t(two, one, 0).se, 0.03 * one.mean[0]) << options << ": too few runs to see a bias";
  for (int i = 0; i < kLargeRegions; ++i) {
    const WelchT w = welch_t(two, one, i);
    EXPECT_GT(student_t_two_sided_p(w.t, w.dof), alpha)
        << options << ", " << large_region_name(i) << ": two ranks " << two.mean[i] << " ± " << two.se[i]
        << ", one process " << one.mean[i] << " ± " << one.se[i] << " (t " << w.t << ")";
  }
}

// The largest relative difference of two images over every pixel and channel (NaN: infinite).
double largest_relative_difference(const ImageRGB& a, const ImageRGB& b, std::size_t* at = nullptr) {
  EXPECT_EQ(a.rgb.size(), b.rgb.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.rgb.size(), b.rgb.size()); ++i) {
    const double x = a.rgb[i], y = b.rgb[i], scale = std::max(std::abs(x), std::abs(y));
    const double relative = scale > 0.0 ? std::abs(x - y) / scale : 0.0;
    if (!(relative <= worst)) {
      worst = std::isnan(relative) ? INFINITY : relative;
      if (at) *at = i;
    }
  }
  return worst;
}

// PT's samples are a pure function of (seed, pixel, sample index): two ranks, each with its slices of
// the same rounds, give the one-process image up to the order of float sums.
TEST(Ranks, TwoRanksGiveTheOneProcessPathTracedImage) {
  const std::string dir = fresh_dir("ranks_pt");
  const std::string common = "render " + kCornell + "--mode pt --width 64 --height 64 --spp 64 --seed 7 ";
  const CliResult one = run_cli(common + "--out " + dir + "/one --stats " + dir + "/one.json");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const CliResult two = run_on_two_ranks(common + "--out " + dir + "/two --stats " + dir + "/two.json");
  ASSERT_EQ(two.exit_code, 0) << two.output;
  EXPECT_EQ(count_of(two.output, "bundlepath: rendering "), 1u) << "rank 0 alone speaks:\n" << two.output;

  const nlohmann::json one_stats = read_stats(dir + "/one.json"), two_stats = read_stats(dir + "/two.json");
  EXPECT_EQ(one_stats["ranks"], 1);
  EXPECT_EQ(two_stats["ranks"], 2);
  EXPECT_EQ(two_stats["spp"], 64);
  const std::uint64_t rank0 = two_stats["devices"][0]["pt_samples"];  // rank 0's part: rank 1 did the rest
  EXPECT_GT(rank0, 16u) << two_stats.dump();
  EXPECT_LT(rank0, 48u) << two_stats.dump();

  const ImageRGB a = read_exr(dir + "/two.exr"), b = read_exr(dir + "/one.exr");
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  double sum = 0.0;
  for (float v : b.rgb) sum += v;
  EXPECT_GT(sum, 0.0);
  std::size_t worst_at = 0;
  const double worst = largest_relative_difference(a, b, &worst_at);
  std::printf("largest relative difference, two ranks against one process: %.3g\n", worst);
  EXPECT_LT(worst, 1e-4) << "pixel " << worst_at / 3 << " channel " << worst_at % 3 << ": " << a.rgb[worst_at]
                         << " on two ranks, " << b.rgb[worst_at] << " in one process";
}

// A checkpoint written by rank 0 of two and resumed on two ranks: PT gives one process's
// uninterrupted image (the checkpoint holds the reduced sums; the batches end on the same grid).
TEST(Ranks, StoppedAndResumedOnTwoRanksEqualsOneProcess) {
  const std::string dir = fresh_dir("ranks_checkpoint");
  const std::string common = "render " + kCornell + "--mode pt --width 32 --height 32 --seed 3 ";
  ASSERT_EQ(run_cli(common + "--spp 48 --out " + dir + "/whole").exit_code, 0);
  CliResult r = run_on_two_ranks(common + "--spp 16 --checkpoint " + dir + "/ck --out " + dir + "/first");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_on_two_ranks(common + "--spp 48 --resume " + dir + "/ck --out " + dir + "/rest --stats " + dir +
                       "/rest.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json stats = read_stats(dir + "/rest.json");
  EXPECT_EQ(stats["resumed_from_rounds"], 16);
  EXPECT_EQ(stats["spp"], 48);
  EXPECT_LT(largest_relative_difference(read_exr(dir + "/rest.exr"), read_exr(dir + "/whole.exr")), 1e-4);
}

TEST(Ranks, RayBundlesOnTwoRanksAgreeWithOneProcess) {
  expect_regions_agree("--width 32 --height 32 --mode rb --iterations 192", 8, fresh_dir("ranks_rb"));
}

// --ratio auto: root's probe picks c and every rank renders with it (the weights need one c); at
// 32x32 that may be the path tracer alone, so a fixed ratio too, which has RB on both ranks.
TEST(Ranks, CombinedOnTwoRanksAgreesWithOneProcess) {
  expect_regions_agree("--width 32 --height 32 --mode combined --spp 24", 6, fresh_dir("ranks_combined"));
  expect_regions_agree("--width 32 --height 32 --mode combined --ratio 1/2 --spp 24", 6, fresh_dir("ranks_combined_fixed"));
}

// --time: root decides when the time is up and every rank stops at that round (a rank that went on
// would wait forever for the others in the next batch's reduction: mpirun's timeout fails the test).
TEST(Ranks, TimeStopsEveryRankAtTheSameRound) {
  const std::string dir = fresh_dir("ranks_time");
  const CliResult r = run_on_two_ranks("render " + kCornell + "--width 32 --height 32 --mode combined --ratio 1 " +
                                       "--time 1.5 --out " + dir + "/t --stats " + dir + "/t.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json stats = read_stats(dir + "/t.json");
  const std::uint64_t rounds = stats["rounds"], rank0 = stats["devices"][0]["pt_samples"];
  EXPECT_GE(rounds, 2u) << stats.dump();
  EXPECT_EQ(stats["spp"], rounds);
  EXPECT_EQ(stats["iterations"], rounds);
  EXPECT_GT(rank0, 0u);
  EXPECT_LT(rank0, rounds);
  EXPECT_FALSE(stats["interrupted"].get<bool>());
}

// Ctrl-C on mpirun: Open MPI sends the ranks SIGTERM odls_base_sigkill_timeout seconds later (and
// SIGKILL as long after that); they agree to stop after the batch they are in, and rank 0 writes the
// image of the rounds done. mpirun itself exits 1 (the job it ended), so the stats tell.
TEST(Ranks, SigintOnMpirunWritesTheRoundsDone) {
  const std::string dir = fresh_dir("ranks_sigint");
  // The same kernels once first, so neither rank is still building them when the signal comes (a
  // SIGTERM then ends PoCL's linker, and the rank with it, before it has a batch to finish).
  const CliResult warm = run_on_two_ranks("render " + kCornell + "--width 32 --height 32 --mode combined --ratio 1 "
                                          "--spp 1 --out " + dir + "/warm");
  ASSERT_EQ(warm.exit_code, 0) << warm.output;
  const std::string render = kTwoRanks + "--mca odls_base_sigkill_timeout 5 '" + std::string(BP_BINARY) +
                             "' render " + kCornell +
                             "--width 32 --height 32 --mode combined --ratio 1 --spp 100000000 --out " + dir +
                             "/i --stats " + dir + "/s.json";
  const CliResult r = run_shell(render + " 2>" + dir + "/log & pid=$!; for i in $(seq 600); do grep -q rendering " +
                                dir + "/log && break; sleep 0.1; done; sleep 1; kill -INT $pid; wait $pid; " +
                                "echo \"exit=$?\"; cat " + dir + "/log");
  ASSERT_TRUE(fs::exists(dir + "/s.json")) << r.output;
  const nlohmann::json stats = read_stats(dir + "/s.json");
  EXPECT_TRUE(stats["interrupted"].get<bool>()) << r.output;
  EXPECT_EQ(stats["ranks"], 2);
  const std::uint64_t rounds = stats["rounds"];
  EXPECT_GE(rounds, 1u);
  EXPECT_EQ(stats["spp"], rounds);
  const ImageRGB img = read_exr(dir + "/i.exr");
  double sum = 0;
  for (float v : img.rgb) sum += v;
  EXPECT_GT(sum, 0.0);
}

// A walkthrough's views are one process's (its views share one RB chain): refused on two ranks with
// exit 2 and one line naming mpirun, nothing written.
TEST(Ranks, WalkthroughOnTwoRanksIsRefused) {
  const std::string dir = fresh_dir("ranks_walkthrough");
  const CliResult r = run_on_two_ranks("render " + std::string(BP_SOURCE_DIR) +
                                       "/tests/data/gltf/good/cornell-walk.gltf --cameras all --width 16 --height 16 "
                                       "--spp 1 --out " + dir + "/w");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("mpirun"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/w_0000.exr"));
}

}  // namespace
}  // namespace bp::test
#endif  // BP_MPIRUN

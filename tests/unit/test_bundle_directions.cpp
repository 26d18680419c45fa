// The ray-bundle iterations' direction sequences (passes/bundle_directions.h): every point uniform on
// the unit square, each stratified sequence visiting every cell once, consecutive directions within
// the interleave independent, the warm-up and the independent sequence untouched.
#include "passes/bundle_directions.h"

#include "kernels/shared/rng.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <set>
#include <vector>

namespace bp {
namespace {
using test::ChiSquareResult;
using test::chi_square_test;
using test::sidak_alpha;

constexpr std::uint64_t kWarmup = 16;

UnitSquarePoint random_jitter(Rng* rng) {
  UnitSquarePoint j;
  j.u1 = rng_uniform(rng);
  j.u2 = rng_uniform(rng);
  return j;
}

std::uint32_t cell_of(UnitSquarePoint p) {
  const auto side = kStratifiedCellsPerSide;
  const std::uint32_t x = std::min(side - 1, std::uint32_t(p.u1 * float(side)));
  const std::uint32_t y = std::min(side - 1, std::uint32_t(p.u2 * float(side)));
  return y * side + x;
}

TEST(BundleDirections, EachSequenceOfABlockVisitsEveryCellOnce) {
  Rng rng = rng_init(3, 11, 0);
  for (std::uint32_t seed : {1u, 2u, 977u})
    for (std::uint64_t block : {0ull, 1ull, 5ull, 12345ull})
      for (std::uint32_t s = 0; s < kStratifiedInterleave; ++s) {
        std::set<std::uint32_t> cells;
        for (std::uint32_t v = 0; v < kStratifiedCells; ++v) {
          const std::uint64_t it = kWarmup + block * kStratifiedBlock + v * kStratifiedInterleave + s;
          const UnitSquarePoint p =
              bundle_direction_point(DirectionSequence::stratified, seed, it, kWarmup, random_jitter(&rng));
          ASSERT_GE(p.u1, 0.0f);
          ASSERT_LE(p.u1, 1.0f);
          ASSERT_GE(p.u2, 0.0f);
          ASSERT_LE(p.u2, 1.0f);
          cells.insert(cell_of(p));
        }
        EXPECT_EQ(cells.size(), kStratifiedCells) << "seed " << seed << " block " << block << " sequence " << s;
      }
}

TEST(BundleDirections, TheWarmupAndTheIndependentSequenceAreTheIterationsOwnPoints) {
  const UnitSquarePoint jitter{0.3f, 0.8f};
  for (std::uint64_t it : {0ull, 7ull, 15ull}) {
    const UnitSquarePoint p = bundle_direction_point(DirectionSequence::stratified, 5, it, kWarmup, jitter);
    EXPECT_EQ(p.u1, jitter.u1);
    EXPECT_EQ(p.u2, jitter.u2);
  }
  for (std::uint64_t it : {16ull, 100ull, 1ull << 40}) {
    const UnitSquarePoint p = bundle_direction_point(DirectionSequence::independent, 5, it, kWarmup, jitter);
    EXPECT_EQ(p.u1, jitter.u1);
    EXPECT_EQ(p.u2, jitter.u2);
  }
}

// Over seeds, one iteration's point is uniform on the square (chi-square over an 8x8 grid), at
// several places of a block: the first visit, a middle one, the last.
TEST(BundleDirections, EveryIterationsPointIsUniformOverSeeds) {
  constexpr int kSeeds = 20000, kSide = 8;
  const std::vector<std::uint64_t> places = {kWarmup, kWarmup + 37, kWarmup + kStratifiedBlock - 1,
                                             kWarmup + 9 * kStratifiedBlock + 22};
  const double alpha = sidak_alpha(1e-3, int(places.size()));
  for (std::uint64_t it : places) {
    std::vector<double> observed(kSide * kSide, 0.0), expected(kSide * kSide, double(kSeeds) / (kSide * kSide));
    for (std::uint32_t seed = 1; seed <= kSeeds; ++seed) {
      Rng rng = rng_init(seed, 0x77u, std::uint32_t(it));
      const UnitSquarePoint p =
          bundle_direction_point(DirectionSequence::stratified, seed, it, kWarmup, random_jitter(&rng));
      const int x = std::min(kSide - 1, int(p.u1 * kSide)), y = std::min(kSide - 1, int(p.u2 * kSide));
      observed[y * kSide + x] += 1.0;
    }
    const ChiSquareResult r = chi_square_test(observed, expected);
    EXPECT_GT(r.p_value, alpha) << "iteration " << it << ": chi2 " << r.statistic << " (" << r.dof << " dof)";
  }
}

// Directions up to kStratifiedInterleave - 1 iterations apart belong to different sequences: their
// cells are independent (chi-square of the 16 x 16 pair table over seeds). Iterations exactly
// kStratifiedInterleave apart in a block share a sequence and never a cell.
TEST(BundleDirections, ConsecutiveDirectionsAreIndependentWithinTheInterleave) {
  constexpr int kSeeds = 40000;
  const std::uint64_t first = kWarmup + 3 * kStratifiedBlock + 5;
  const double alpha = sidak_alpha(1e-3, int(kStratifiedInterleave - 1));
  for (std::uint32_t lag = 1; lag < kStratifiedInterleave; ++lag) {
    std::vector<double> observed(kStratifiedCells * kStratifiedCells, 0.0),
        expected(observed.size(), double(kSeeds) / double(observed.size()));
    for (std::uint32_t seed = 1; seed <= kSeeds; ++seed) {
      const UnitSquarePoint mid{0.5f, 0.5f};
      const std::uint32_t a = cell_of(bundle_direction_point(DirectionSequence::stratified, seed, first, kWarmup, mid));
      const std::uint32_t b =
          cell_of(bundle_direction_point(DirectionSequence::stratified, seed, first + lag, kWarmup, mid));
      observed[a * kStratifiedCells + b] += 1.0;
    }
    const ChiSquareResult r = chi_square_test(observed, expected);
    EXPECT_GT(r.p_value, alpha) << "lag " << lag << ": chi2 " << r.statistic << " (" << r.dof << " dof)";
  }
  for (std::uint32_t seed = 1; seed <= 200; ++seed) {
    const UnitSquarePoint mid{0.5f, 0.5f};
    EXPECT_NE(cell_of(bundle_direction_point(DirectionSequence::stratified, seed, first, kWarmup, mid)),
              cell_of(bundle_direction_point(DirectionSequence::stratified, seed, first + kStratifiedInterleave,
                                             kWarmup, mid)));
  }
}

}  // namespace
}  // namespace bp

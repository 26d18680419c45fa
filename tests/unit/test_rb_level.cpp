// --rb-level corrected's arithmetic (image/rb_level.h): the inverse-variance factor, the levels and
// standard errors from batch means, a resumed state, and -- by simulation on the host -- that the
// corrected level is centred on the truth and far less noisy than RB's own.
#include "image/rb_level.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp::test {
namespace {

TEST(RbLevel, FactorIsTheInverseVarianceMeanOverRbsLevel) {
  // Equal variances: the plain mean of the two levels.
  EXPECT_DOUBLE_EQ(rb_level_factor(2.0, 0.1, 1.0, 0.1), 1.5 / 2.0);
  // Var_RB = 3 Var_PT: weights 1/4 and 3/4.
  EXPECT_DOUBLE_EQ(rb_level_factor(2.0, 0.3, 1.0, 0.1), (0.25 * 2.0 + 0.75 * 1.0) / 2.0);
  // PT exact: PT's level; RB exact: RB's own (factor 1).
  EXPECT_DOUBLE_EQ(rb_level_factor(2.0, 0.1, 1.0, 0.0), 0.5);
  EXPECT_DOUBLE_EQ(rb_level_factor(2.0, 0.0, 1.0, 0.1), 1.0);
}

TEST(RbLevel, FactorIsOneWhereItCannotBeTrusted) {
  EXPECT_EQ(rb_level_factor(2.0, std::nan(""), 1.0, 0.1), 1.0);  // fewer than two batches
  EXPECT_EQ(rb_level_factor(2.0, 0.1, 1.0, std::nan("")), 1.0);
  EXPECT_EQ(rb_level_factor(0.0, 0.1, 1.0, 0.1), 1.0);           // no RB share to scale
  EXPECT_EQ(rb_level_factor(-1.0, 0.1, 1.0, 0.1), 1.0);
  EXPECT_EQ(rb_level_factor(2.0, 0.0, 1.0, 0.0), 1.0);           // both exact
  EXPECT_EQ(rb_level_factor(1.0, 0.1, -3.0, 0.1), 1.0);          // a mean <= 0
  EXPECT_EQ(rb_level_factor(INFINITY, 0.1, 1.0, 0.1), 1.0);
}

// A two-pixel image whose rounds add, per pixel and channel, RB's weighted value rb_value and PT's
// weighted w and unweighted w + pt_complement.
const RegionGrid kWhole = RegionGrid::over(2, 1, 1, 1);
struct Rounds {
  Accumulator pt{2, 1, true}, rb{2, 1, false};
  void add(double rb_value, double pt_complement, double w = 0.25) {
    for (std::size_t i = 0; i < rb.sum.size(); ++i) {
      rb.sum[i] += rb_value;
      pt.sum[i] += w;
      pt.raw_sum[i] += w + pt_complement;
    }
    ++rb.samples_per_pixel;
    ++pt.samples_per_pixel;
  }
};

TEST(RbLevel, LevelsAndStandardErrorsAreTheBatchMeans) {
  Rounds r;
  RbLevel level(kWhole, 0, r.pt, 1, r.rb, 1, std::nullopt);
  // Batches of one round: RB 1, 3 (mean 2, s^2 = 2, Var of the mean 1); PT 0.5 twice (variance 0).
  r.add(1.0, 0.5);
  level.add(1);
  r.add(3.0, 0.5);
  level.add(2);
  EXPECT_EQ(level.batches(), 2u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_DOUBLE_EQ(level.rb_levels()[0][c], 2.0);
    EXPECT_DOUBLE_EQ(level.pt_levels()[0][c], 0.5);
    EXPECT_DOUBLE_EQ(level.rb_standard_errors()[0][c], 1.0);
    EXPECT_DOUBLE_EQ(level.pt_standard_errors()[0][c], 0.0);
    EXPECT_DOUBLE_EQ(level.factors()[0][c], 0.25);  // PT exact: its level 0.5 over RB's 2
  }
}

TEST(RbLevel, ResumedStateContinuesTheSameBatches) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  Rounds whole, part;
  RbLevel uninterrupted(kWhole, 0, whole.pt, 1, whole.rb, 1, std::nullopt);
  std::optional<RbLevel> first(std::in_place, kWhole, 0, part.pt, 1, part.rb, 1, std::nullopt);
  std::optional<RbLevel> resumed;
  for (std::uint64_t round = 1; round <= 12; ++round) {
    const double a = 1.0 + noise(rng), b = 0.9 + noise(rng);
    whole.add(a, b);
    part.add(a, b);
    uninterrupted.add(round);
    if (round <= 5) {
      first->add(round);
    } else {
      if (!resumed) resumed.emplace(kWhole, 5, part.pt, 1, part.rb, 1, first->state());
      resumed->add(round);
    }
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_DOUBLE_EQ(resumed->factors()[0][c], uninterrupted.factors()[0][c]);
    EXPECT_DOUBLE_EQ(resumed->rb_standard_errors()[0][c], uninterrupted.rb_standard_errors()[0][c]);
  }
}

// --rb-level regional: on a 4x3 grid of regions whose RB layer varies smoothly over the image and
// whose PT estimate of the share differs per region, the field scales each region's RB layer by
// exactly that region's factor (its mean of field · rb over its mean of rb), and is smooth: no
// step between neighbouring pixels larger than the factors' own differences allow.
TEST(RbLevel, RegionalFieldGivesEachRegionItsOwnFactor) {
  constexpr int kWidth = 40, kHeight = 30;
  const RegionGrid grid = RegionGrid::over(kWidth, kHeight, 4, 3);
  Accumulator pt(kWidth, kHeight, true), rb(kWidth, kHeight, false);
  RbLevel level(grid, 0, pt, 1, rb, 1, std::nullopt);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (std::uint64_t round = 1; round <= 8; ++round) {
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const std::size_t region = grid.region_of(x, y);
        const double rb_value = 0.5 + 0.01 * x + 0.02 * y + noise(rng);
        const double share = rb_value * (0.9 + 0.02 * double(region)) + 0.1 * noise(rng);  // PT's, per region
        for (int c = 0; c < 3; ++c) {
          const std::size_t i = (std::size_t(y) * kWidth + std::size_t(x)) * 3 + std::size_t(c);
          rb.sum[i] += rb_value;
          pt.sum[i] += 0.2;
          pt.raw_sum[i] += 0.2 + share;
        }
      }
    ++rb.samples_per_pixel;
    ++pt.samples_per_pixel;
    level.add(round);
  }
  const std::vector<std::array<double, 3>> factors = level.factors();
  const std::vector<double> field = level.pixel_factors();
  std::vector<double> scaled(field.size());
  for (std::size_t i = 0; i < field.size(); ++i) scaled[i] = field[i] * rb.sum[i];
  const std::vector<double> with = grid.sums(scaled), without = grid.sums(rb.sum);
  double spread = 0.0;
  for (std::size_t r = 0; r < grid.count(); ++r) {
    spread = std::max(spread, std::fabs(factors[r][0] - factors[0][0]));
    for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(with[r * 3 + c] / without[r * 3 + c], factors[r][c], 1e-4) << r;
  }
  EXPECT_GT(spread, 0.05) << "the regions' factors should differ here";
  double largest_step = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 1; x < kWidth; ++x) {
      const std::size_t i = (std::size_t(y) * kWidth + std::size_t(x)) * 3;
      largest_step = std::max(largest_step, std::fabs(field[i] - field[i - 3]));
    }
  EXPECT_LT(largest_step, 0.5 * spread) << "the field should be smooth, not one step per region edge";
}

// The estimator on simulated renders: RB's level per round is the truth plus a large noise shared by
// every pixel, PT's estimate of it the truth plus a small one. Over many renders, the corrected level
// M_RB · s must be centred on the truth (z-test of its mean) with a variance close to the
// inverse-variance optimum, far below RB's own.
TEST(RbLevel, CorrectedLevelIsCentredAndFarLessNoisyThanRbsOwn) {
  constexpr double kTruth = 0.4, kRbSd = 0.2, kPtSd = 0.02;
  constexpr int kRenders = 2000, kRounds = 40;
  std::mt19937 rng(11);
  std::normal_distribution<double> rb_noise(0.0, kRbSd), pt_noise(0.0, kPtSd);
  double sum_own = 0, sum_sq_own = 0, sum_corrected = 0, sum_sq_corrected = 0;
  for (int k = 0; k < kRenders; ++k) {
    Rounds r;
    RbLevel level(kWhole, 0, r.pt, 1, r.rb, 1, std::nullopt);
    for (std::uint64_t round = 1; round <= kRounds; ++round) {
      r.add(kTruth + rb_noise(rng), kTruth + pt_noise(rng));
      level.add(round);
    }
    const double own = level.rb_levels()[0][0], corrected = own * level.factors()[0][0];
    sum_own += own;
    sum_sq_own += own * own;
    sum_corrected += corrected;
    sum_sq_corrected += corrected * corrected;
  }
  const double mean_corrected = sum_corrected / kRenders;
  const double var_own = sum_sq_own / kRenders - (sum_own / kRenders) * (sum_own / kRenders);
  const double var_corrected = sum_sq_corrected / kRenders - mean_corrected * mean_corrected;
  const double var_optimum = 1.0 / (kRounds / (kRbSd * kRbSd) + kRounds / (kPtSd * kPtSd));
  EXPECT_LT(std::fabs(mean_corrected - kTruth) / std::sqrt(var_corrected / kRenders), 4.0)
      << "mean " << mean_corrected << ", truth " << kTruth;
  EXPECT_NEAR(var_own, kRbSd * kRbSd / kRounds, 0.2 * kRbSd * kRbSd / kRounds);  // the simulation itself
  // Estimated weights cost a little over the optimum (40 batches); RB's own is 100x the optimum.
  EXPECT_LT(var_corrected, 1.3 * var_optimum) << "own " << var_own << ", optimum " << var_optimum;
}

}  // namespace
}  // namespace bp::test

// The batch-means error estimate (image/error_estimate.h, docs/design.md §9) on synthetic rounds whose
// variance is known: independent Gaussian rounds (PT's case) and an AR(1) chain (RB's case, a
// Markov chain whose batches must outlast its correlation).
#include "image/error_estimate.h"
#include "passes/checkpoint.h"
#include "passes/render_loop.h"
#include "estimate_reference.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

namespace bp::test {
namespace {

constexpr int kWidth = 32, kHeight = 32;
constexpr std::size_t kValues = std::size_t(kWidth) * kHeight * 3;

// Independent rounds, per value i mean mu_i and variance sigma_i², fed in the render loop's batches
// (1, 2, 4, ..., 16, then 16s: unequal lengths). Σ_i (K − 1) s_i² / σ_i² is exactly χ² with
// values · (K − 1) degrees of freedom for Gaussian rounds, whatever the batch lengths.
TEST(ErrorEstimate, IndependentRoundsGiveTheVarianceOfTheMean) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  std::vector<double> mu(kValues), sigma(kValues), sums(kValues, 0.0);
  for (std::size_t i = 0; i < kValues; ++i) {
    mu[i] = 0.05 + 2.0 * double(i % 97) / 97.0;
    sigma[i] = 0.1 + double(i % 13) / 4.0;
  }
  const std::uint64_t rounds = 200;
  BatchMeansErrorEstimate estimate(kWidth, kHeight, 1);
  const RoundSums view{&sums};
  for (std::uint64_t done = 0; done < rounds;) {
    const std::uint32_t n = batch_size(done, rounds, 16);
    for (std::uint32_t r = 0; r < n; ++r)
      for (std::size_t i = 0; i < kValues; ++i) sums[i] += mu[i] + sigma[i] * normal(rng);
    done += n;
    estimate.add(done, view);
  }
  const std::uint64_t k = estimate.batches();
  ASSERT_EQ(k, 5u + (rounds - 16) / 16 + 1);  // 1, 2, 4, 8, 16 ... then the last, cut at 200
  const std::vector<double> var = estimate.variance_of_mean();
  ASSERT_EQ(var.size(), kValues);
  double chi2 = 0.0;
  for (std::size_t i = 0; i < kValues; ++i) chi2 += var[i] * double(rounds) * double(k - 1) / (sigma[i] * sigma[i]);
  const double dof = double(kValues) * double(k - 1);
  const double z = (chi2 - dof) / std::sqrt(2.0 * dof);  // χ² of ~10⁵ dof is normal to within 10⁻²
  EXPECT_LT(std::fabs(z), z_for_two_sided(0.001)) << "chi2 " << chi2 << " dof " << dof;

  // The relMSE is the mean of Var / (R̂² + 0.01), R̂ the smaller of the pixel and the mean of its 8
  // (at the border 3 or 5) neighbours in the image I = sums / rounds, channel by channel.
  ImageRGB image(kWidth, kHeight);
  for (std::size_t i = 0; i < kValues; ++i) image.rgb[i] = float(sums[i] / double(rounds));
  const double expected = estimated_rel_mse_of(image, var);
  EXPECT_NEAR(estimate.estimated_rel_mse(image), expected, 1e-9 * expected);
  EXPECT_NEAR(estimate.estimated_rel_mse(view), expected, 1e-5 * expected);
}

// Fireflies (issue #16): rounds of 0.5 · Exp(1) plus, with probability 0.02, a spike of 10 -- the
// mean 0.7, the variance 0.25 + 100 · 0.02 · 0.98 -- at 16 rounds in the render loop's batches
// (1, 2, 4, 8, 1). A spike raises a value's variance estimate and the value together, so dividing by
// the value itself gives about 0.46 of the true relMSE; with the smaller of it and its neighbours' mean
// in place of R the estimate is within 1.4x of it (1.17 ± 0.05 over 30 seeds of a simulation of this
// set-up: the smaller of two noisy values is a little low).
TEST(ErrorEstimate, FirefliesDoNotHideTheirOwnVariance) {
  std::mt19937_64 rng(5);
  std::exponential_distribution<double> exponential(1.0);
  std::bernoulli_distribution spike(0.02);
  const double mean = 0.5 + 0.02 * 10.0, variance = 0.25 + 100.0 * 0.02 * 0.98;
  const std::uint64_t rounds = 16;
  std::vector<double> sums(kValues, 0.0);
  BatchMeansErrorEstimate estimate(kWidth, kHeight, 1);
  for (std::uint64_t done = 0; done < rounds;) {
    const std::uint32_t n = batch_size(done, rounds, 8);
    for (std::uint32_t r = 0; r < n; ++r)
      for (double& s : sums) s += 0.5 * exponential(rng) + (spike(rng) ? 10.0 : 0.0);
    done += n;
    estimate.add(done, RoundSums{&sums});
  }
  ASSERT_EQ(estimate.batches(), 5u);
  const double truth = variance / double(rounds) / (mean * mean + 0.01);  // docs/design.md §7 at R = the mean
  const double ratio = estimate.estimated_rel_mse(RoundSums{&sums}) / truth;
  EXPECT_GT(ratio, 1.0 / 1.4);
  EXPECT_LT(ratio, 1.4);
}

// b · Var(mean of b rounds) / σ² of a stationary AR(1) chain x_t = ρ x_{t−1} + sqrt(1 − ρ²) σ ε_t.
double ar1_batch_factor(double rho, double b) {
  return (1.0 + rho) / (1.0 - rho) - 2.0 * rho * (1.0 - std::pow(rho, b)) / (b * (1.0 - rho) * (1.0 - rho));
}

// A Markov chain (RB's iterations): batches of one round see only the per-round variance, 1/9 of the
// truth at ρ = 0.8; batches of 64 (8× the integrated correlation time 9) see all but the known
// finite-batch shortfall, ar1_batch_factor(64) / ar1_batch_factor(∞) = 0.93. The levels are the
// blocking study of bench/error_estimate.sh.
TEST(ErrorEstimate, CorrelatedRoundsNeedBatchesLongerThanTheCorrelation) {
  const double rho = 0.8;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  std::vector<double> x(kValues), sums(kValues, 0.0);
  for (double& v : x) v = normal(rng);  // stationary start, σ = 1
  const std::uint64_t rounds = 64 * 128;
  BatchMeansErrorEstimate estimate(kWidth, kHeight, 1, 7);  // batches of 1, 2, 4, ..., 64 rounds
  const RoundSums view{&sums};
  const double innovation = std::sqrt(1.0 - rho * rho);
  for (std::uint64_t t = 1; t <= rounds; ++t) {
    for (std::size_t i = 0; i < kValues; ++i) {
      x[i] = rho * x[i] + innovation * normal(rng);
      sums[i] += 1.0 + x[i];
    }
    estimate.add(t, view);
  }
  const double truth = ar1_batch_factor(rho, double(rounds)) / double(rounds);  // Var of the mean of all rounds
  auto mean_ratio = [&](int level) {
    const std::vector<double> var = estimate.variance_of_mean(level);
    double s = 0.0;
    for (double v : var) s += v / truth;
    return s / double(var.size());
  };
  ASSERT_EQ(estimate.batch_rounds(6), 64u);
  ASSERT_EQ(estimate.batches(6), 128u);
  const double infinite = (1.0 + rho) / (1.0 - rho);
  // Tolerances: 3072 independent values; a batch of 64 has 127 degrees of freedom, so the mean
  // ratio's standard error is about sqrt(2/127) · 1.2 (correlated neighbour batches) / sqrt(3072) ≈ 0.003.
  EXPECT_NEAR(mean_ratio(0), ar1_batch_factor(rho, 1) / infinite, 0.01);
  EXPECT_NEAR(mean_ratio(6), ar1_batch_factor(rho, 64) / infinite, 0.03);
  EXPECT_LT(mean_ratio(0), 0.2) << "batches of one round must miss the chain's correlation";
  for (int j = 1; j < 7; ++j) EXPECT_GT(mean_ratio(j), mean_ratio(j - 1)) << "level " << j;
}

// The combination's image is the sum of two independent layers, each estimated from batches of its
// own length (ImageErrorEstimate): independent rounds (PT's, batches of one round) and an AR(1)
// chain (RB's, batches of 32 rounds), fed in the render loop's batches. Their variances add, the
// stderr layer is the root of the sum, and the degrees of freedom are Welch–Satterthwaite's: K − 1
// for one layer, at most the sum of the layers' for two, and between the least and that sum.
TEST(ErrorEstimate, IndependentLayersAddTheirVariancesAndFreedoms) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal;
  std::vector<double> pt_sums(kValues, 0.0), rb_sums(kValues, 0.0), chain(kValues, 0.0);
  const double rho = 0.5, innovation = std::sqrt(1.0 - rho * rho);
  ImageErrorEstimate both(kWidth, kHeight, {{"pt", {&pt_sums, 0.5}, 1}, {"rb", {&rb_sums, 1.0}, 32}}, 1, 0);
  ImageErrorEstimate pt_alone(kWidth, kHeight, {{"pt", {&pt_sums, 0.5}, 1}}, 1, 0);
  const std::uint64_t rounds = 400;
  for (std::uint64_t done = 0; done < rounds;) {
    const std::uint32_t n = batch_size(done, rounds, 16);
    for (std::uint32_t r = 0; r < n; ++r)
      for (std::size_t i = 0; i < kValues; ++i) {
        pt_sums[i] += 1.0 + 0.8 * normal(rng);
        chain[i] = rho * chain[i] + innovation * normal(rng);
        rb_sums[i] += 0.5 + 0.3 * chain[i];
      }
    done += n;
    if (done < 64) {
      EXPECT_EQ(both.degrees_of_freedom(), 0.0) << "the chain's layer has no two batches yet";
    }
    both.add(done);
    pt_alone.add(done);
  }
  const BatchMeansErrorEstimate &pt = both.layers()[0], &rb = both.layers()[1];
  ASSERT_EQ(pt.batches(), 5u + (rounds - 16) / 16);  // 1, 2, 4, 8, 16, then 16s
  ASSERT_GE(rb.batches(), 10u);
  ASSERT_LT(rb.batches(), pt.batches());
  const std::vector<double> pt_var = pt.variance_of_mean(), rb_var = rb.variance_of_mean();
  std::vector<double> var(kValues);
  ImageRGB image(kWidth, kHeight);
  for (std::size_t i = 0; i < kValues; ++i) {
    var[i] = pt_var[i] + rb_var[i];  // each of the layer as it counts in the image (PT's sums at half)
    image.rgb[i] = float((0.5 * pt_sums[i] + rb_sums[i]) / double(rounds));
  }
  const ImageRGB se = both.standard_error();
  for (std::size_t i : {std::size_t(0), std::size_t(5), kValues - 1}) EXPECT_FLOAT_EQ(se.rgb[i], float(std::sqrt(var[i])));
  const double expected = estimated_rel_mse_of(image, var);
  EXPECT_NEAR(both.estimated_rel_mse(), expected, 1e-5 * expected);
  EXPECT_NEAR(both.layer_rel_mse(0) + both.layer_rel_mse(1), expected, 1e-9 * expected);
  // Each layer's variance is right: 0.25 · 0.64 / N for PT's, 0.09 · (1 + ρ)/(1 − ρ) / N for the chain's
  // (its batches of 32+ rounds see all but a few percent of it), averaged over 3072 values.
  double pt_ratio = 0.0, rb_ratio = 0.0;
  for (std::size_t i = 0; i < kValues; ++i) {
    pt_ratio += pt_var[i] * double(rounds) / (0.25 * 0.64) / double(kValues);
    rb_ratio += rb_var[i] * double(rounds) / (0.09 * ar1_batch_factor(rho, double(rounds))) / double(kValues);
  }
  EXPECT_NEAR(pt_ratio, 1.0, 0.02);
  EXPECT_NEAR(rb_ratio, ar1_batch_factor(rho, 32) / ar1_batch_factor(rho, 1e9), 0.06);
  // Welch–Satterthwaite.
  const double v_pt = both.layer_rel_mse(0), v_rb = both.layer_rel_mse(1);
  const double k_pt = double(pt.batches()) - 1.0, k_rb = double(rb.batches()) - 1.0;
  const double dof = (v_pt + v_rb) * (v_pt + v_rb) / (v_pt * v_pt / k_pt + v_rb * v_rb / k_rb);
  EXPECT_NEAR(both.degrees_of_freedom(), dof, 1e-9 * dof);
  EXPECT_GT(both.degrees_of_freedom(), std::min(k_pt, k_rb));
  EXPECT_LE(both.degrees_of_freedom(), k_pt + k_rb);
  EXPECT_EQ(pt_alone.degrees_of_freedom(), k_pt);
}

// RB's layer checked against PT's estimate of its share (rb_bias_rel_mse): PT's weighted layer w and
// unweighted u = w + d, RB's r scaled by 0.9 in the image, in batches of 4 rounds. RB's noise is a
// chain's: one fluctuation common to every pixel per round (a room's light moving together) beside
// each pixel's own. Without a bias the check is its noise: counted (a false alarm) in at most 10 % of
// the renders (5 % by design). With s·r 0.1 off d's mean, above it in one half of the image and below
// in the other (a discretisation's blur), it estimates the relMSE of that bias without bias (the mean
// of 40 renders within 15 %, about 3 of its standard errors) and counts it in 9 renders of 10 or more.
// A standard error √K too small (K the increments) gave 45 false alarms in 200
// renders (tried; 5 as it is).
struct RbBiasRender {
  double counted, estimate;
  ImageRGB image;
};
RbBiasRender render_rb_bias_check(double bias, std::uint64_t seed) {
  constexpr int kW = 16, kH = 16;
  constexpr std::size_t kN = std::size_t(kW) * kH * 3;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<double> w_sums(kN, 0.0), u_sums(kN, 0.0), rb_sums(kN, 0.0);
  constexpr double kFactor = 0.9;
  ImageErrorEstimate e(kW, kH, {{"pt", {&w_sums, 1.0}, 1}, {"rb", {&rb_sums, 1.0}, 4}}, 1, 0, nullptr,
                       RoundSums{&u_sums, 1.0, &w_sums});
  e.set_factors("rb", std::vector<double>(kN, kFactor));
  const std::uint64_t rounds = 128;
  for (std::uint64_t done = 0; done < rounds;) {
    const std::uint32_t n = batch_size(done, rounds, 8);
    for (std::uint32_t r = 0; r < n; ++r) {
      const double common = 0.4 * normal(rng);
      for (std::size_t i = 0; i < kN; ++i) {
        const double w = 0.2 + 0.3 * normal(rng), d = 0.5 + 0.8 * normal(rng);
        w_sums[i] += w;
        u_sums[i] += w + d;
        const double sign = i < kN / 2 ? 1.0 : -1.0;  // a discretisation's: too bright here, too dark there
        rb_sums[i] += (0.5 + sign * bias + common) / kFactor + 0.3 * normal(rng);
      }
    }
    done += n;
    e.add(done);
  }
  RbBiasRender out{e.rb_bias_rel_mse(), e.rb_bias_check().estimate, ImageRGB(kW, kH)};
  for (std::size_t i = 0; i < kN; ++i) out.image.rgb[i] = float((w_sums[i] + kFactor * rb_sums[i]) / double(rounds));
  // The image's estimate counts it beside the layers' variances.
  EXPECT_NEAR(e.estimated_rel_mse(), e.layer_rel_mse(0) + e.layer_rel_mse(1) + out.counted, 1e-12);
  return out;
}

TEST(ErrorEstimate, RbBiasIsSeenAgainstPtsEstimateOfTheShareAndTheChainsNoiseIsNot) {
  constexpr int kRenders = 200;
  int false_alarms = 0;
  for (int k = 0; k < kRenders; ++k) false_alarms += render_rb_bias_check(0.0, 100 + std::uint64_t(k)).counted > 0.0;
  EXPECT_LE(false_alarms, kRenders / 10);
  double sum = 0.0;
  int seen = 0;
  constexpr int kBiased = 40;
  for (int k = 0; k < kBiased; ++k) {
    const RbBiasRender r = render_rb_bias_check(0.1, 1000 + std::uint64_t(k));
    const double expected = estimated_rel_mse_of(r.image, std::vector<double>(r.image.rgb.size(), 0.1 * 0.1));
    seen += r.counted > 0.0;
    sum += r.estimate / expected;
  }
  EXPECT_GE(seen, kBiased * 9 / 10);
  EXPECT_NEAR(sum / kBiased, 1.0, 0.15);
}

TEST(ErrorEstimate, FewerThanTwoBatchesHaveNoEstimate) {
  std::vector<double> sums(kValues, 1.0);
  BatchMeansErrorEstimate estimate(kWidth, kHeight, 64);
  estimate.add(32, RoundSums{&sums});
  EXPECT_TRUE(std::isnan(estimate.estimated_rel_mse(RoundSums{&sums})));
  EXPECT_TRUE(estimate.variance_of_mean().empty());
  ImageErrorEstimate image_estimate(kWidth, kHeight, {{"rb", {&sums, 1.0}, 64}}, 1, 0);
  image_estimate.add(32);
  EXPECT_TRUE(std::isnan(image_estimate.estimated_rel_mse()));
  EXPECT_EQ(image_estimate.degrees_of_freedom(), 0.0);
  const ImageRGB se = image_estimate.standard_error();  // zeros until two batches
  ASSERT_EQ(se.rgb.size(), kValues);
  EXPECT_EQ(se.rgb[7], 0.0f);
}

// The statistics survive a checkpoint (the resumed estimate continues the same batches), and a
// checkpoint of before issue #16 (format 01, no statistics) and one of before --rb-level (format 02)
// still read.
TEST(ErrorEstimate, StatisticsSurviveACheckpoint) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u;
  std::vector<double> sums(kValues, 0.0);
  BatchMeansErrorEstimate estimate(kWidth, kHeight, 4, 2);
  for (std::uint64_t t = 1; t <= 40; ++t) {
    for (double& s : sums) s += u(rng);
    if (t % 3 == 0) estimate.add(t, RoundSums{&sums});
  }
  const std::string dir = BP_BUILD_DIR "/test-out/error_estimate_checkpoint";
  std::filesystem::create_directories(dir);
  Checkpoint c;
  c.options = "x";
  c.rounds = 39;
  c.error_estimate = {estimate.state()};
  c.rb_bias_sums = {0.5, 0.25, 3.0, 1.5, 9.0, 7};
  write_checkpoint(dir + "/ck", c);
  Checkpoint back = read_checkpoint(dir + "/ck");
  ASSERT_EQ(back.error_estimate.size(), 1u);
  EXPECT_EQ(back.rb_bias_sums.e, 0.5);
  EXPECT_EQ(back.rb_bias_sums.a_sq, 9.0);
  EXPECT_EQ(back.rb_bias_sums.batches, 7u);
  BatchMeansErrorEstimate resumed = BatchMeansErrorEstimate::from_state(back.error_estimate[0], kWidth, kHeight);
  EXPECT_EQ(resumed.variance_of_mean(0), estimate.variance_of_mean(0));
  EXPECT_EQ(resumed.variance_of_mean(1), estimate.variance_of_mean(1));
  EXPECT_EQ(resumed.batches(1), estimate.batches(1));
  EXPECT_THROW(BatchMeansErrorEstimate::from_state(back.error_estimate[0], kWidth, kHeight + 1), std::runtime_error);

  c.error_estimate.clear();
  write_checkpoint(dir + "/v1", c);
  std::ifstream in(dir + "/v1", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  // Format 05 ends before 06's sums of the check of RB's layer (five doubles and a count), 04 before
  // 05's count of regional layers (one byte, 0 here); 03 has a presence byte where 04 has the count
  // of layers (0 here: the same bytes), 02 ends before the RB level's two presence bytes, 01 also
  // before the error estimate's.
  for (const char version : {'5', '4', '3', '2', '1'}) {
    bytes[7] = version;
    bytes.resize(bytes.size() - (version == '5' ? 48 : version == '4' ? 1 : version == '3' ? 0 : version == '2' ? 2 : 1));
    std::ofstream(dir + "/old", std::ios::binary) << bytes;
    Checkpoint old = read_checkpoint(dir + "/old");
    EXPECT_EQ(old.rounds, 39u);
    EXPECT_TRUE(old.error_estimate.empty());
    EXPECT_FALSE(old.rb_level);
    EXPECT_FALSE(old.regional_error);
  }
}

// RB's batches are 64 iterations unless a render is expected to hold fewer than four of them: then
// the longest whole blocks of 16 that give four (at least one block), so it still has an estimate.
TEST(ErrorEstimate, AShortRenderGetsShorterRbBatches) {
  EXPECT_EQ(rb_error_batch_iterations(std::nan("")), kErrorBatchRbIterations);
  EXPECT_EQ(rb_error_batch_iterations(1e6), kErrorBatchRbIterations);
  EXPECT_EQ(rb_error_batch_iterations(256.0), 64u);
  EXPECT_EQ(rb_error_batch_iterations(255.0), 48u);
  EXPECT_EQ(rb_error_batch_iterations(128.0), 32u);
  EXPECT_EQ(rb_error_batch_iterations(80.0), 16u);  // 5 batches, not 1
  EXPECT_EQ(rb_error_batch_iterations(3.0), 16u);
  for (double n : {70.0, 100.0, 150.0, 200.0, 250.0}) {
    const std::uint64_t batch = rb_error_batch_iterations(n);
    EXPECT_EQ(batch % kErrorBatchRbBlock, 0u) << n;
    EXPECT_GE(n / double(batch), double(kErrorBatchesWanted)) << n;
  }
}

}  // namespace
}  // namespace bp::test

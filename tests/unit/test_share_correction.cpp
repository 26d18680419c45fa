// --rb-level consistent's arithmetic (image/share_correction.h), by simulation on the host: a smooth
// true share t, RB's estimate r exact but for a sharp 6x6-pixel dip of 30 % (a contact shadow RB's
// patches smear: RB reads the undimmed value there), and PT's unbiased estimate d = t + noise of variance sigma^2 / N after N rounds.
#include "image/share_correction.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp::test {
namespace {

constexpr int kWidth = 96, kHeight = 64;
constexpr double kSigma = 0.5;  // a pixel's PT noise per round, on a share of about 0.5

double truth(int x, int y) { return 0.4 + 0.2 * std::sin(0.05 * x) * std::cos(0.07 * y); }
bool in_dip(int x, int y) { return x >= 40 && x < 46 && y >= 30 && y < 36; }

struct Trial {
  double dip_mse = 0.0, dip_mean_error = 0.0;  // over the dip's pixels and channels
  double rest_mse = 0.0;                       // elsewhere, where r is exact
  double left_in_dip = 0.0;                    // the error the correction reports there
};

Trial run(double rounds, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, kSigma / std::sqrt(rounds));
  ImageRGB r(kWidth, kHeight), d(kWidth, kHeight);
  std::vector<double> variance(std::size_t(kWidth) * kHeight * 3, kSigma * kSigma / rounds);
  // The true share is 0.7 t in the dip, which RB's patches smear away: RB reads t there.
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) {
        const double t = truth(x, y);
        r.pixel(x, y)[c] = float(t);
        d.pixel(x, y)[c] = float((in_dip(x, y) ? 0.7 * t : t) + noise(rng));
      }
  const ShareCorrection s = correct_share(r, d, variance);
  Trial trial;
  int dip = 0, rest = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) {
        const double t = in_dip(x, y) ? 0.7 * truth(x, y) : truth(x, y);
        const double e = s.share.pixel(x, y)[c] - t;
        if (in_dip(x, y)) {
          trial.dip_mse += e * e;
          trial.dip_mean_error += e;
          trial.left_in_dip += s.left_error[(std::size_t(y) * kWidth + std::size_t(x)) * 3 + std::size_t(c)];
          ++dip;
        } else {
          trial.rest_mse += e * e;
          ++rest;
        }
      }
  trial.dip_mse /= dip;
  trial.dip_mean_error /= dip;
  trial.left_in_dip /= dip;
  trial.rest_mse /= rest;
  return trial;
}

TEST(ShareCorrection, WhereRbIsExactPtsNoiseHardlyLeaksIn) {
  // At every budget the corrected share keeps RB's (exact) values within a few percent of PT's
  // variance: the threshold keeps blocks of pure noise from being corrected.
  for (double rounds : {4.0, 64.0, 1024.0}) {
    const Trial t = run(rounds, 7);
    EXPECT_LT(t.rest_mse, 0.03 * kSigma * kSigma / rounds) << rounds << " rounds";
  }
}

TEST(ShareCorrection, RbsBiasIsCorrectedAsPtSharpensSoTheShareConverges) {
  // RB is off by 0.3 t (about 0.12) over the dip; PT's noise per pixel is 0.25 at 4 rounds, 0.004 at
  // 16384. The dip's error must keep falling with the rounds, to PT's own noise at the end.
  double previous = INFINITY;
  for (double rounds : {4.0, 64.0, 1024.0, 16384.0}) {
    const Trial t = run(rounds, 11);
    EXPECT_LT(t.dip_mse, previous) << rounds << " rounds";
    previous = t.dip_mse;
  }
  const double rounds = 16384.0, pixel_variance = kSigma * kSigma / rounds;
  const Trial t = run(rounds, 13);
  // Within a few times PT's own variance (the dip's 108 values: its mean error within 4 standard
  // errors of PT's noise over them), where RB's bias alone would be 0.12^2 = 1.4e-2.
  EXPECT_LT(t.dip_mse, 3.0 * pixel_variance);
  EXPECT_LT(std::abs(t.dip_mean_error), 4.0 * std::sqrt(pixel_variance / 108.0));
}

TEST(ShareCorrection, WhatItLeavesOfRbsBiasItReports) {
  // Early (PT too noisy to see the dip at the pixel level), the error the correction reports over
  // the dip is about its real error there; the report is not the noise's.
  const Trial t = run(16.0, 17);
  EXPECT_GT(t.left_in_dip, 0.3 * t.dip_mse);
  EXPECT_LT(t.left_in_dip, 3.0 * t.dip_mse);
}

TEST(ShareCorrection, UnknownVarianceLeavesRbsShareAsItIs) {
  ImageRGB r(4, 4), d(4, 4);
  for (float& v : r.rgb) v = 0.5f;
  EXPECT_EQ(correct_share(r, d, {}).share.rgb, r.rgb);
  EXPECT_EQ(correct_share(r, d, std::vector<double>(48, std::nan(""))).share.rgb, r.rgb);
}

}  // namespace
}  // namespace bp::test

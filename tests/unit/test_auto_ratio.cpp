// --ratio auto's rule (passes/combined.h): c = f / (1 - f) · t_RB / t_PT, snapped to a power of 2.
#include "passes/combined.h"

#include <gtest/gtest.h>
#include <cmath>
#include <utility>

namespace bp {
namespace {

TEST(AutoRatio, GivesPtItsShareOfTheTime) {
  for (double f : {auto_ratio_pt_time_share(false), auto_ratio_pt_time_share(true)})
    for (double t_pt : {1e-4, 3e-3, 0.2})
      for (double t_rb : {1e-4, 2e-3, 0.05}) {
        const RoundShape shape = auto_ratio_shape(t_pt, t_rb, f, AutoRatioBounds{0.0, false});
        const double share_wanted = t_rb > t_pt ? std::max(f, kAutoRatioPtTimeShareRbCostly) : f;
        const double c = shape.ratio(), exact = share_wanted / (1 - share_wanted) * t_rb / t_pt;
        EXPECT_EQ(std::exp2(std::round(std::log2(c))), c) << "a power of 2";
        if (exact > 1.0 / 1024 && exact < 64) {
          EXPECT_LE(std::fabs(std::log2(c / exact)), 0.5 + 1e-9) << f << " " << t_pt << " " << t_rb;
          const double share = shape.pt_samples * t_pt / (shape.pt_samples * t_pt + shape.rb_iterations * t_rb);
          EXPECT_NEAR(share, share_wanted, 0.15) << t_pt << " " << t_rb;
        }
        EXPECT_EQ(round_shape(c).pt_samples, shape.pt_samples);
        EXPECT_EQ(round_shape(c).rb_iterations, shape.rb_iterations);
      }
}

// An RB iteration dearer than a PT sample of the whole image (the house at 128x128: t_RB/t_PT ≈ 2):
// the path tracer alone, whatever the share asked for; where the render counts RB iterations
// (--iterations) PT gets at least kAutoRatioPtTimeShareRbCostly (c = 0.98/0.02 · 2 = 98 -> 64, the
// largest). One a little cheaper keeps the share asked for.
TEST(AutoRatio, ChoosesThePathTracerAloneWhereAnRbIterationCostsMoreThanAPtSample) {
  const AutoRatioBounds counts_iterations{0.0, false};
  for (bool pt_alone : {false, true}) {
    const double f = auto_ratio_pt_time_share(pt_alone);
    EXPECT_TRUE(auto_ratio_shape(0.045, 0.090, f).pt_alone());
    EXPECT_EQ(auto_ratio_shape(0.045, 0.090, f).pt_samples, 1u);
    EXPECT_TRUE(std::isinf(auto_ratio_shape(0.090, 0.095, f).ratio()));
    EXPECT_EQ(auto_ratio_shape(0.045, 0.090, f, counts_iterations).ratio(), 64.0);
    EXPECT_EQ(auto_ratio_shape(0.090, 0.095, f, counts_iterations).ratio(), 64.0);  // 0.98/0.02 · 1.06 = 52 -> 64
    for (const AutoRatioBounds& bounds : {AutoRatioBounds{}, counts_iterations}) {
      const RoundShape cheaper = auto_ratio_shape(0.100, 0.090, f, bounds);
      EXPECT_FALSE(cheaper.pt_alone());
      EXPECT_EQ(cheaper.ratio(), std::exp2(std::round(std::log2(f / (1 - f) * 0.9))));
    }
  }
  // PT alone: PT unweighted (w_PT = 1), as --mode pt.
  EXPECT_EQ(combined_weights(BP_WEIGHTS_PRODUCT, RoundShape{1, 0}).mode, BP_WEIGHTS_NONE);
  EXPECT_EQ(combined_weights(BP_WEIGHTS_PRODUCT, RoundShape{1, 0}).ratio_n2_over_n1, 0.0f);
}

// A round longer than the --time is halved until it fits, N2 first (the Phong house at 1280x720:
// t_PT = 2.98 s, t_RB = 0.2 s, 16 s: c = 1/128 is a 28.6 s round, 1/64 one of 15.8 s).
TEST(AutoRatio, ChoosesARoundThatFitsTheTimeBudget) {
  const double f = auto_ratio_pt_time_share(false);
  EXPECT_EQ(auto_ratio_shape(2.98, 0.2, f).rb_iterations, 128u);
  const RoundShape fits = auto_ratio_shape(2.98, 0.2, f, AutoRatioBounds{16.0, true});
  EXPECT_EQ(fits.pt_samples, 1u);
  EXPECT_EQ(fits.rb_iterations, 64u);
  EXPECT_EQ(auto_ratio_shape(2.98, 0.2, f, AutoRatioBounds{100.0, true}).rb_iterations, 128u);  // fits already
  // c >= 1: N1 halved once N2 is 1 (t_RB/t_PT = 0.9 at the share 0.65: c = 1.67 -> 2, a 0.029 s round).
  const double f_pt = auto_ratio_pt_time_share(true);
  const RoundShape wide = auto_ratio_shape(0.01, 0.009, f_pt);
  ASSERT_GT(wide.pt_samples, 1u);
  const RoundShape narrowed = auto_ratio_shape(0.01, 0.009, f_pt, AutoRatioBounds{0.0095 + 0.01, true});
  EXPECT_EQ(narrowed.rb_iterations, 1u);
  EXPECT_EQ(narrowed.pt_samples, 1u);
  // Nothing fits: the smallest round, one of each.
  const RoundShape smallest = auto_ratio_shape(2.98, 0.2, f, AutoRatioBounds{1.0, true});
  EXPECT_EQ(smallest.pt_samples, 1u);
  EXPECT_EQ(smallest.rb_iterations, 1u);
}

TEST(AutoRatio, StaysWithinItsRange) {
  const double f = auto_ratio_pt_time_share(false);
  EXPECT_EQ(auto_ratio_shape(1.0, 1e-9, f).rb_iterations, 1024u);
  EXPECT_EQ(auto_ratio_shape(1e-9, 1.0, f, AutoRatioBounds{0.0, false}).pt_samples, 64u);
  // equal (clamped) costs: f / (1 - f), snapped to a power of 2
  EXPECT_EQ(auto_ratio_shape(0.0, 0.0, f).ratio(), std::ldexp(1.0, int(std::lround(std::log2(f / (1.0 - f))))));
}

// PT gets the larger share where the eye vertex's direct light is its alone (passes/combined.h).
TEST(AutoRatio, LeansToPtWhereTheEyeDirectLightIsPtsAlone) {
  EXPECT_EQ(auto_ratio_pt_time_share(false), kAutoRatioPtTimeShareEyeShared);
  EXPECT_EQ(auto_ratio_pt_time_share(true), kAutoRatioPtTimeShareEyePt);
  EXPECT_GT(kAutoRatioPtTimeShareEyePt, kAutoRatioPtTimeShareEyeShared);
  EXPECT_GT(auto_ratio_shape(2e-3, 1e-3, auto_ratio_pt_time_share(true)).ratio(),
            auto_ratio_shape(2e-3, 1e-3, auto_ratio_pt_time_share(false)).ratio());
}

// Glossy scenes: PT's share minimises κ / f + β / (1 − f) (κ the share of PT's variance its
// weights keep, β RB's part); it grows with κ, is 1/2 where κ = β, is not asked for where κ is not
// measured, and the probed share is never below the base share.
TEST(AutoRatio, GivesPtMoreTimeTheMoreOfItsVarianceItsWeightsKeep) {
  const double beta = kAutoRatioRbVarianceOverPt;
  EXPECT_NEAR(gloss_pt_time_share(beta), 0.5, 1e-12);
  double previous = 0.0;
  for (double kappa : {1e-4, 1e-3, 0.01, 0.05, 0.2, 0.5, 1.0}) {
    const double f = gloss_pt_time_share(kappa);
    EXPECT_GT(f, previous) << kappa;
    previous = f;
    // The model's least: no share 0.01 either side does better.
    const auto rel_mse = [&](double g) { return kappa / g + beta / (1 - g); };
    EXPECT_LE(rel_mse(f), rel_mse(std::min(f + 0.01, 0.999))) << kappa;
    EXPECT_LE(rel_mse(f), rel_mse(std::max(f - 0.01, 0.001))) << kappa;
    for (double base : {kAutoRatioPtTimeShareEyeShared, kAutoRatioPtTimeShareEyePt})
      EXPECT_EQ(probed_pt_time_share(base, kappa), std::max(base, f));
  }
  EXPECT_EQ(gloss_pt_time_share(std::nan("")), 0.0);
  EXPECT_EQ(gloss_pt_time_share(0.0), 0.0);
  EXPECT_EQ(gloss_pt_time_share(3.0), gloss_pt_time_share(1.0));  // κ is at most 1
  EXPECT_EQ(probed_pt_time_share(kAutoRatioPtTimeShareEyeShared, std::nan("")), kAutoRatioPtTimeShareEyeShared);
}

}  // namespace
}  // namespace bp

namespace bp {
namespace {

// PT's probe image: the render's own size up to 128x128 pixels, else the same view scaled to about
// that many pixels with the aspect kept.
TEST(AutoRatio, ProbeImageIsTheSameViewAtAbout128SquaredPixels) {
  EXPECT_EQ(probe_image_size(20, 20).width, 20);
  EXPECT_EQ(probe_image_size(128, 128).height, 128);
  for (auto [w, h] : {std::pair{640, 360}, std::pair{1280, 720}, std::pair{4096, 100}}) {
    const ProbeImageSize s = probe_image_size(w, h);
    EXPECT_NEAR(double(s.width) * s.height, double(kAutoRatioProbePixels), 0.05 * kAutoRatioProbePixels) << w << "x" << h;
    EXPECT_NEAR(double(s.width) / s.height, double(w) / h, 0.05 * w / h) << w << "x" << h;
  }
}

}  // namespace
}  // namespace bp

namespace bp {
namespace {

// --mode combined with --ratio auto and no budget renders as long as --mode pt's default 64 spp
// would take: that time over a round's, at least one round (the Cornell box at 512x512: t_PT =
// 0.142 s, t_RB = 0.009 s, c = 1/128: 9.1 s over 1.29 s rounds, 7 rounds).
TEST(AutoRatio, NoBudgetRendersAsLongAsThePathTracersDefault) {
  EXPECT_EQ(equal_time_rounds(64, RoundShape{1, 128}, 0.1418, 0.009), 7u);
  EXPECT_EQ(equal_time_rounds(64, RoundShape{1, 0}, 0.05, 0.1), 64u);  // the path tracer alone: 64 spp
  EXPECT_EQ(equal_time_rounds(64, RoundShape{4, 1}, 0.01, 0.01), 13u);  // 0.64 s over 0.05 s
  EXPECT_EQ(equal_time_rounds(1, RoundShape{1, 128}, 0.1, 1.0), 1u);    // at least one round
  // No costs (a resumed render, no probe): 64 PT samples' worth of rounds.
  EXPECT_EQ(equal_time_rounds(64, RoundShape{1, 128}, 0.0, 0.0), 64u);
  EXPECT_EQ(equal_time_rounds(64, RoundShape{4, 1}, 0.0, 0.0), 16u);
}

}  // namespace
}  // namespace bp

// The shared kernel headers compiled as C++: BRDF, pdfs, the q/r state of eq. (9), the RNG.
#include "stats.h"

#include "kernels/shared/brdf.h"
#include "kernels/shared/path_pdf.h"
#include "kernels/shared/rng.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp::test {
namespace {

Bsdf make_bsdf(float kd, float ks, float n) {
  Material m{};
  for (int c = 0; c < 3; ++c) { m.kd[c] = kd; m.ks[c] = ks; }
  m.shininess = n;
  return bsdf_from_material(&m);
}

float3 dir_from_angles(double theta, double phi) {
  return make_float3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                     float(std::cos(theta)));
}

// Integral over the upper hemisphere of g(w) dw, midpoint rule in (cos theta, phi).
template <class F>
double hemisphere_integral(F g, int n = 400) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double mu = (i + 0.5) / n, phi = 2 * M_PI * (j + 0.5) / n;
      sum += g(dir_from_angles(std::acos(mu), phi));
    }
  return sum * 2 * M_PI / (double(n) * n);
}

TEST(Brdf, ReciprocalAndNonNegative) {
  Bsdf b = make_bsdf(0.3f, 0.6f, 40.0f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const float3 n = make_float3(0, 0, 1);
  for (int i = 0; i < 1000; ++i) {
    float3 wi = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
    float3 wo = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
    float3 a = bsdf_eval(&b, n, wi, wo), c = bsdf_eval(&b, n, wo, wi);
    EXPECT_NEAR(a.x, c.x, 1e-4f * std::max(1.0f, a.x));
    EXPECT_GE(a.x, 0.0f);
  }
}

TEST(Brdf, LambertAlbedoIsKdAndPhongNeverGainsEnergy) {
  const float3 n = make_float3(0, 0, 1);
  const float3 wo = dir_from_angles(0.4, 0.0);
  Bsdf lambert = make_bsdf(0.7f, 0.0f, 1.0f);
  EXPECT_NEAR(hemisphere_integral([&](float3 wi) { return bsdf_eval(&lambert, n, wi, wo).x * wi.z; }), 0.7, 1e-3);
  for (float shininess : {1.0f, 10.0f, 50.0f, 1000.0f}) {
    Bsdf phong = make_bsdf(0.0f, 1.0f, shininess);
    for (double theta : {0.0, 0.7, 1.3}) {
      float3 w = dir_from_angles(theta, 0.3);
      double albedo = hemisphere_integral([&](float3 wi) { return bsdf_eval(&phong, n, wi, w).x * wi.z; }, 1200);
      EXPECT_LE(albedo, 1.0 + 2e-3) << "n = " << shininess << " theta = " << theta;
    }
  }
}

TEST(Pdf, CosineIntegratesToOneAndPhongToAtMostOne) {
  const float3 n = make_float3(0, 0, 1);
  const float3 wo = dir_from_angles(0.5, 1.0);
  Bsdf diffuse = make_bsdf(0.8f, 0.0f, 1.0f);
  EXPECT_NEAR(hemisphere_integral([&](float3 wi) { return bsdf_pdf_uv(&diffuse, n, wi, wo) / (2 * M_PI); }), 1.0, 1e-3);
  Bsdf phong = make_bsdf(0.0f, 0.9f, 20.0f);
  double mass = hemisphere_integral([&](float3 wi) { return bsdf_pdf_uv(&phong, n, wi, wo) / (2 * M_PI); }, 1000);
  EXPECT_LE(mass, 1.0 + 1e-3);
  EXPECT_GT(mass, 0.9);  // the lobe around the mirror of a near-normal wo lies mostly above the surface
  // Along the normal, wo = n: the whole lobe is above the surface, so it integrates to one.
  double full = hemisphere_integral([&](float3 wi) { return bsdf_pdf_uv(&phong, n, wi, n) / (2 * M_PI); }, 1000);
  EXPECT_NEAR(full, 1.0, 2e-3);
}

TEST(PathPdf, MatchesEquationNineInDoubleAndNeverOverflows) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  for (int path = 0; path < 200; ++path) {
    PathPdf p = path_pdf_start();
    double log_q = 0.0, r = 0.0;  // double reference, q kept as its log
    int length = 1 + int(u(rng) * 400);
    for (int k = 0; k < length; ++k) {
      double s = 0.05 + 0.95 * u(rng);
      double pdf = std::exp(std::log(1e-4) + u(rng) * std::log(1e9));  // 1e-4 .. 1e5
      // (9): r_k = (1-s) q_{k-1} + r_{k-1};  q_k = s p q_{k-1}
      double log_terminated = std::log(1 - s) + log_q;
      double log_r = r > 0 ? std::log(r) : -1e300;
      double hi = std::max(log_terminated, log_r);
      r = std::exp(hi + std::log(std::exp(log_terminated - hi) + std::exp(log_r - hi)));
      log_q += std::log(s) + std::log(pdf);
      path_pdf_step(&p, float(s), float(pdf));
      ASSERT_TRUE(std::isfinite(p.log_q) && std::isfinite(p.log_r));
      ASSERT_NEAR(p.log_q, log_q, 1e-5 * std::max(1.0, std::fabs(log_q)) * (k + 1));
      if (std::isfinite(std::log(r))) {
        ASSERT_NEAR(p.log_r, std::log(r), 1e-5 * std::max(1.0, std::fabs(std::log(r))) * (k + 1));
      }
    }
    double w = pt_emission_weight(&p, BP_WEIGHTS_PAPER, 3.0f);
    ASSERT_TRUE(std::isfinite(w) && w >= 0.0 && w <= 1.0);
  }
}

TEST(PathPdf, PaperWeightIsEquationFour) {
  // One bounce: P* = s p + (1 - s); w_PT = N1 P* / (N1 P* + N2) with N2/N1 = ratio.
  PathPdf p = path_pdf_start();
  path_pdf_step(&p, 0.6f, 1.7f);
  double pstar = 0.6 * 1.7 + 0.4, ratio = 0.25;
  EXPECT_NEAR(pt_emission_weight(&p, BP_WEIGHTS_PAPER, float(ratio)), pstar / (pstar + ratio), 1e-6);
  EXPECT_EQ(pt_emission_weight(&p, BP_WEIGHTS_NONE, float(ratio)), 1.0f);
  PathPdf empty = path_pdf_start();  // the eye sees an emitter: P* = 1
  EXPECT_NEAR(pt_emission_weight(&empty, BP_WEIGHTS_PAPER, 2.0f), 1.0 / 3.0, 1e-6);
}

TEST(Rng, UniformInUnitIntervalAndDeterministic) {
  std::vector<double> observed(64, 0.0), expected(64, 0.0);
  const int n = 1 << 18;
  for (int i = 0; i < n; ++i) {
    Rng r = rng_init(123u, std::uint32_t(i), 7u);
    float x = rng_uniform(&r);
    ASSERT_GE(x, 0.0f);
    ASSERT_LT(x, 1.0f);
    observed[std::size_t(x * 64)] += 1;
    for (int k = 0; k < 5; ++k) rng_uniform(&r);  // later draws must not disturb the first
  }
  for (double& e : expected) e = n / 64.0;
  EXPECT_GT(chi_square_test(observed, expected).p_value, 0.001);
  Rng a = rng_init(1u, 2u, 3u), b = rng_init(1u, 2u, 3u), c = rng_init(1u, 2u, 4u);
  std::uint32_t xa = rng_next_u32(&a), xb = rng_next_u32(&b), xc = rng_next_u32(&c);
  EXPECT_EQ(xa, xb);
  EXPECT_NE(xa, xc);
}

TEST(Rng, Philox4x32KnownAnswer) {
  // Random123's known-answer test for philox4x32-10: key (0,0), counter 0 ->
  // 6627e8d5 e169c58d bc57ac4c 9b00dbd8.
  const bp_u32 key[2] = {0u, 0u}, ctr[4] = {0u, 0u, 0u, 0u};
  bp_u32 out[4];
  philox4x32_10(key, ctr, out);
  EXPECT_EQ(out[0], 0x6627e8d5u);
  EXPECT_EQ(out[1], 0xe169c58du);
  EXPECT_EQ(out[2], 0xbc57ac4cu);
  EXPECT_EQ(out[3], 0x9b00dbd8u);
}

}  // namespace
}  // namespace bp::test

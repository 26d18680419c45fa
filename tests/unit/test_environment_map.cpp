// The environment map's directions and sampling (kernels/shared/environment_map.h, compiled as C++)
// against docs/design.md §6's convention and against its own pdf: +Y up, the centre column along -Z;
// a piecewise-constant distribution by luminance x sin(theta), pdf_solid = pdf_image / (2 pi^2 sin theta).
#include "stats.h"

#include "kernels/shared/environment_map.h"
#include "scene/environment_map.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp::test {
namespace {

// A small map, far from uniform: a bright sun-like texel, a dim band, a black row and black texels.
EnvironmentImage non_uniform_map() {
  EnvironmentImage m;
  m.width = 8;
  m.height = 4;
  m.rgb.assign(std::size_t(m.width) * m.height * 3, 0.0f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (int row = 0; row < m.height; ++row)
    for (int column = 0; column < m.width; ++column)
      for (int c = 0; c < 3; ++c)
        m.rgb[(std::size_t(row) * m.width + column) * 3 + c] = row == 2 || column == 5 ? 0.0f : uniform(rng) * (c + 1);
  float* sun = &m.rgb[(std::size_t(1) * m.width + 3) * 3];
  sun[0] = 40.0f, sun[1] = 30.0f, sun[2] = 20.0f;
  return m;
}

struct PackedMap {
  std::vector<float> data;
  EnvironmentMap view;
  explicit PackedMap(const EnvironmentImage& m)
      : data(pack_environment(m)), view(environment_map(data.data(), std::uint32_t(m.width), std::uint32_t(m.height))) {}
};

TEST(EnvironmentMap, DirectionsFollowTheDesignConvention) {
  const auto near = [](float3 a, float x, float y, float z) {
    EXPECT_NEAR(a.x, x, 1e-6f);
    EXPECT_NEAR(a.y, y, 1e-6f);
    EXPECT_NEAR(a.z, z, 1e-6f);
  };
  near(environment_direction(0.5f, 0.5f), 0.0f, 0.0f, -1.0f);  // the centre column, at the horizon: -Z
  near(environment_direction(0.75f, 0.5f), 1.0f, 0.0f, 0.0f);  // a quarter turn to the right: +X
  near(environment_direction(0.25f, 0.5f), -1.0f, 0.0f, 0.0f);
  near(environment_direction(0.0f, 0.5f), 0.0f, 0.0f, 1.0f);   // the image's edges: +Z, behind
  near(environment_direction(0.3f, 0.0f), 0.0f, 1.0f, 0.0f);   // the top row: +Y
  near(environment_direction(0.3f, 1.0f), 0.0f, -1.0f, 0.0f);
}

TEST(EnvironmentMap, DirectionToUvRoundTrips) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (int i = 0; i < 10000; ++i) {
    const float u = uniform(rng), v = 0.001f + 0.998f * uniform(rng);
    float u2, v2;
    environment_uv(environment_direction(u, v), &u2, &v2);
    EXPECT_NEAR(v2, v, 2e-5f);
    EXPECT_NEAR(std::remainder(u2 - u, 1.0f), 0.0f, 2e-5f) << u << " " << v;
    const float3 d = environment_direction(u2, v2), e = environment_direction(u, v);
    EXPECT_NEAR(dot(d, e), 1.0f, 1e-5f);
  }
}

TEST(EnvironmentMap, LookupIsTheNearestTexel) {
  const EnvironmentImage m = non_uniform_map();
  const PackedMap p(m);
  for (int row = 0; row < m.height; ++row)
    for (int column = 0; column < m.width; ++column) {
      const float3 l = environment_radiance(&p.view, environment_direction((column + 0.5f) / m.width, (row + 0.5f) / m.height));
      const float* t = &m.rgb[(std::size_t(row) * m.width + column) * 3];
      EXPECT_EQ(l.x, t[0]);
      EXPECT_EQ(l.y, t[1]);
      EXPECT_EQ(l.z, t[2]);
    }
}

// The integral over the sphere of pdf_solid, midpoint rule in (theta, phi): 1.
TEST(EnvironmentMap, PdfIntegratesToOneOverTheSphere) {
  const PackedMap p(non_uniform_map());
  const int n_theta = 800, n_phi = 1600;
  double integral = 0.0;
  for (int i = 0; i < n_theta; ++i)
    for (int j = 0; j < n_phi; ++j) {
      const double v = (i + 0.5) / n_theta, u = (j + 0.5) / n_phi;
      const float3 d = environment_direction(float(u), float(v));
      integral += environment_pdf_solid_angle(&p.view, d) * std::sin(M_PI * v) * (M_PI / n_theta) * (2.0 * M_PI / n_phi);
    }
  EXPECT_NEAR(integral, 1.0, 1e-3);
}

// A sample's pdf is the pdf of its direction; no sample lands where the pdf is 0; a uniform map
// samples uniformly over the image square.
TEST(EnvironmentMap, SamplePdfMatchesThePdfOfItsDirection) {
  const PackedMap p(non_uniform_map());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const int samples = 20000;
  int other_cell = 0;  // a sample on a texel's edge may round to the neighbour's: rare
  for (int i = 0; i < samples; ++i) {
    const EnvironmentSample s = environment_sample(&p.view, uniform(rng), uniform(rng));
    ASSERT_GT(s.pdf_solid_angle, 0.0f);
    const float ratio = environment_pdf_solid_angle(&p.view, s.wi) / s.pdf_solid_angle;
    const float3 l = environment_radiance(&p.view, s.wi);
    if (std::fabs(ratio - 1.0f) > 1e-3f || !(l.x + l.y + l.z > 0.0f)) ++other_cell;
  }
  EXPECT_LE(other_cell, samples / 2000);
}

// Pearson's chi-square of sample counts in a grid of 2 x 2 cells per texel (uniform within a texel)
// against pdf_image: the routine passes, and the same counts against the wrong (uniform) density fail.
TEST(EnvironmentMap, SamplingPassesChiSquareAgainstItsPdf) {
  const EnvironmentImage m = non_uniform_map();
  const PackedMap p(m);
  const int sub = 2, cols = m.width * sub, rows = m.height * sub, samples = 400000;
  std::vector<double> observed(std::size_t(cols) * rows, 0.0), expected(observed.size()), uniform_expected(observed.size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (int i = 0; i < samples; ++i) {
    const EnvironmentSample s = environment_sample(&p.view, uniform(rng), uniform(rng));
    float u, v;
    environment_uv(s.wi, &u, &v);
    observed[std::size_t(environment_cell(v, rows)) * cols + environment_cell(u, cols)] += 1.0;
  }
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      // each cell is 1 / (cols rows) of the image square, where pdf_image is its texel's
      const double pdf_image = environment_pdf_image(&p.view, std::uint32_t(c / sub), std::uint32_t(r / sub));
      expected[std::size_t(r) * cols + c] = samples * pdf_image / (double(cols) * rows);
      uniform_expected[std::size_t(r) * cols + c] = double(samples) / (double(cols) * rows);
    }
  const ChiSquareResult fit = chi_square_test(observed, expected);
  EXPECT_GT(fit.p_value, 1e-3) << "chi2 " << fit.statistic << " dof " << fit.dof;
  const ChiSquareResult wrong = chi_square_test(observed, uniform_expected);
  EXPECT_LT(wrong.p_value, 1e-6) << "the test cannot tell a wrong density: chi2 " << wrong.statistic;
  // the pdf_image is luminance x sin(theta) over its mean: the sun texel's share
  double total = 0.0;
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c) total += environment_sampling_weight(m, c, r);
  EXPECT_NEAR(environment_pdf_image(&p.view, 3, 1), environment_sampling_weight(m, 3, 1) / total * m.width * m.height,
              1e-4);
}

TEST(EnvironmentMap, UniformRadianceIsTheOneTexelMap) {
  const EnvironmentImage m = uniform_environment(glm::vec3(1.0f, 0.5f, 0.25f));
  ASSERT_EQ(m.width, 1);
  const PackedMap p(m);
  const float3 l = environment_radiance(&p.view, normalize(make_float3(0.3f, -0.4f, 0.2f)));
  EXPECT_EQ(l.x, 1.0f);
  EXPECT_EQ(l.z, 0.25f);
  EXPECT_NEAR(environment_integral(m), 4.0 * M_PI * (1.75 / 3.0), 1e-3);
  EXPECT_TRUE(uniform_environment(glm::vec3(0.0f)).empty());
}

}  // namespace
}  // namespace bp::test

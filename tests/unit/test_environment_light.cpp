// The environment as a light (kernels/shared/lights.h, docs/design.md §3 and §6): last in the list,
// outside the light tree, its p_L one function of the direction that light sampling, PT's BSDF
// samples and RB's bundles all evaluate; light sampling it estimates the irradiance it gives.
#include "environment_maps.h"

#include "kernels/shared/lights.h"
#include "scene/lights.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp::test {
namespace {

struct EnvironmentScene {
  Scene scene;
  LightList list;
  std::vector<float> packed;
  LightSet set;
  explicit EnvironmentScene(bool with_sun) {
    scene.environment_image = std::make_shared<const EnvironmentImage>(graded_sky());
    scene.bounds.grow(glm::vec3(-1.0f));
    scene.bounds.grow(glm::vec3(1.0f));
    if (with_sun) {
      ScenePunctualLight sun;
      sun.kind = ScenePunctualLight::Kind::directional;
      sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
      sun.intensity = glm::vec3(2.0f);
      scene.lights = {sun};
    }
    list = build_light_list(scene, build_bvh(scene.triangles));
    packed = pack_environment(*scene.environment_image);
    set = light_set(list.lights.data(), list.cdf.data(), nullptr, nullptr, std::uint32_t(list.lights.size()),
                    BP_LIGHT_SELECTION_POWER);
    set.environment = environment_map(packed.data(), 8u, 4u);
  }
};

TEST(EnvironmentLight, IsTheLastLightChosenByTheRadianceEnteringTheScene) {
  const EnvironmentScene s(true);
  ASSERT_EQ(s.list.lights.size(), 2u);
  EXPECT_EQ(s.list.environment_light, 1u);
  EXPECT_EQ(s.list.lights[1].type, BP_LIGHT_ENVIRONMENT);
  EXPECT_TRUE(light_is_infinite(s.list.lights[1].type));
  // pi R^2 times the integral of the mean radiance, against the sun's E times what it falls on:
  // nothing in this empty scene, so one cell of sunlit_area's lattice (lights.h)
  const double radius = std::sqrt(3.0), env = M_PI * radius * radius * environment_integral(*s.scene.environment_image);
  const double cell_side = 2.0 * radius / kSunlitGrid, sun = cell_side * cell_side * 2.0;
  EXPECT_NEAR(s.list.lights[1].select_probability, env / (env + sun), 1e-5);
  bp_u32 first = 0u;
  EXPECT_NEAR(light_directional_share(&s.set, &first), 1.0f, 1e-6f);
  EXPECT_EQ(first, 0u);
}

// Every technique's p_L of a direction is light_pdf_uv_environment's, bit for bit the number the
// light sample carried, and the sample is no delta and reaches as far as any ray.
TEST(EnvironmentLight, SampledDensityIsWhatEveryTechniqueEvaluates) {
  const EnvironmentScene s(true);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  int environment_samples = 0;
  for (int i = 0; i < 20000; ++i) {
    const LightSample ls = light_sample(&s.set, nullptr, 0u, make_float3(0, 0, 0), uniform(rng), uniform(rng), uniform(rng));
    if (ls.is_delta) continue;  // the sun
    ++environment_samples;
    EXPECT_EQ(ls.distance, BP_FLOAT_MAX);
    EXPECT_EQ(ls.pdf_uv, light_pdf_uv_environment(&s.set, 0u, s.list.environment_light, ls.wi));
    if (ls.pdf_uv > 0.0f) {
      const float3 l = environment_radiance(&s.set.environment, ls.wi);
      EXPECT_NEAR(ls.radiance_over_pdf.x, l.x * BP_TWO_PI / ls.pdf_uv, 1e-5f * ls.radiance_over_pdf.x);
    }
  }
  EXPECT_GT(environment_samples, 1000);
  EXPECT_EQ(light_pdf_uv_environment(&s.set, 0u, BP_NO_LIGHT, make_float3(0, 1, 0)), 0.0f);  // not sampled: p_L = 0
}

// Next-event estimation's estimator L cos / p_solid, averaged over samples, is the irradiance of a
// plane facing +Y (the lower half, 15x brighter, sampled often and below the plane, adds nothing):
// within 5 standard errors of the analytic value, per channel.
TEST(EnvironmentLight, LightSamplingEstimatesTheIrradianceOfAnUpwardPlane) {
  const EnvironmentScene s(false);
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const int n = 200000;
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const LightSample ls = light_sample(&s.set, nullptr, 0u, make_float3(0, 0, 0), uniform(rng), uniform(rng), uniform(rng));
    const double cos_theta = std::max(0.0f, ls.wi.y);
    const double e[3] = {ls.radiance_over_pdf.x * cos_theta, ls.radiance_over_pdf.y * cos_theta,
                         ls.radiance_over_pdf.z * cos_theta};
    for (int c = 0; c < 3; ++c) {
      sum[c] += e[c];
      sum2[c] += e[c] * e[c];
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / n, se = std::sqrt((sum2[c] / n - mean * mean) / n);
    const double expected = upward_irradiance(*s.scene.environment_image, c);
    EXPECT_LT(se, 0.01 * expected);
    EXPECT_NEAR(mean, expected, 5.0 * se) << "channel " << c;
  }
}

}  // namespace
}  // namespace bp::test

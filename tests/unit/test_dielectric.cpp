// The optics of a refracting dielectric (kernels/shared/dielectric.h): the exact Fresnel equations at
// their limits and against Snell's symmetry, refraction by Snell's law, Beer-Lambert attenuation,
// and the event choice: each event's factor over its probability averages to the event's weight.
#include "kernels/shared/dielectric.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp {
namespace {

TEST(Dielectric, FresnelAtItsLimits) {
  EXPECT_NEAR(dielectric_fresnel(1.5f, 1.0f), 0.04f, 1e-6f);         // normal incidence: ((eta - 1)/(eta + 1))^2
  EXPECT_NEAR(dielectric_fresnel(1.0f / 1.5f, 1.0f), 0.04f, 1e-6f);  // the same from inside
  EXPECT_NEAR(dielectric_fresnel(1.5f, 0.0f), 1.0f, 1e-6f);          // grazing
  EXPECT_NEAR(dielectric_fresnel(1.0f, 0.3f), 0.0f, 1e-7f);          // no interface
  // from inside, past the critical angle asin(1/1.5) = 41.8 degrees: all reflected
  const float critical = std::asin(1.0f / 1.5f);
  EXPECT_EQ(dielectric_fresnel(1.0f / 1.5f, std::cos(critical + 0.01f)), 1.0f);
  EXPECT_LT(dielectric_fresnel(1.0f / 1.5f, std::cos(critical - 0.01f)), 1.0f);
  // Brewster's angle atan(1.5): r_p vanishes, F = r_s^2 / 2 = 0.0739 / 2 (Hecht, Optics, 4.5)
  EXPECT_NEAR(dielectric_fresnel(1.5f, std::cos(std::atan(1.5f))), 0.5f * 0.147929f, 2e-4f);
}

// Light crossing the interface one way meets the same reflectance as crossing it back: F(eta, cos_i)
// = F(1/eta, cos_t), which is what makes a closed clear object conserve a uniform radiance.
TEST(Dielectric, FresnelIsTheSameCrossingEitherWay) {
  for (float cos_i = 0.05f; cos_i <= 1.0f; cos_i += 0.05f) {
    const float sin_t = std::sqrt(1.0f - cos_i * cos_i) / 1.5f, cos_t = std::sqrt(1.0f - sin_t * sin_t);
    EXPECT_NEAR(dielectric_fresnel(1.5f, cos_i), dielectric_fresnel(1.0f / 1.5f, cos_t), 1e-5f) << cos_i;
  }
}

TEST(Dielectric, RefractionFollowsSnellsLawInThePlaneOfIncidence) {
  const float3 n = make_float3(0.0f, 0.0f, 1.0f);
  for (float theta = 0.0f; theta < 1.5f; theta += 0.1f) {
    const float3 wo = make_float3(std::sin(theta), 0.0f, std::cos(theta));
    const float3 wt = refract_through(wo, n, 1.5f);
    EXPECT_NEAR(length(wt), 1.0f, 1e-6f);
    EXPECT_LT(wt.z, 0.0f);                                          // the far side
    EXPECT_NEAR(wt.y, 0.0f, 1e-7f);                                 // in the plane of incidence
    EXPECT_NEAR(-wt.x * 1.5f, std::sin(theta), 1e-5f) << theta;     // sin_i = eta sin_t, across the normal
    const float3 back = refract_through(wt, n * -1.0f, 1.0f / 1.5f);  // from the far side, back along wo
    EXPECT_NEAR(dot(back, wo), 1.0f, 1e-5f) << theta;
  }
}

TEST(Dielectric, BeerLambertAttenuation) {
  const float3 t = medium_transmittance(make_float3(std::log(2.0f), 0.0f, 1e30f), 2.0f);
  EXPECT_NEAR(t.x, 0.25f, 1e-6f);
  EXPECT_EQ(t.y, 1.0f);
  EXPECT_EQ(t.z, 0.0f);
  const float3 far = medium_transmittance(make_float3(0.0f, 0.1f, 0.0f), BP_FLOAT_MAX);  // leaving the scene
  EXPECT_EQ(far.x, 1.0f);
  EXPECT_EQ(far.y, 0.0f);
}

// Over a fine grid of u, the mean of factor [event] is each event's weight: (1 - F) tint / eta^2
// refracted, F T reflected, 1 for the rest (whose BSDF follows); on the way out past the critical
// angle, everything the interface takes is reflected.
TEST(Dielectric, EachEventsFactorOverItsProbabilityAveragesToItsWeight) {
  const float3 n = make_float3(0.0f, 0.0f, 1.0f), tint = make_float3(0.9f, 0.6f, 0.3f);
  const float transmission = 0.8f, rest = 0.15f, ior = 1.5f;
  for (int entering = 0; entering <= 1; ++entering)
    for (float theta : {0.2f, 0.7f, 1.2f}) {
      const float3 wo = make_float3(std::sin(theta), 0.0f, std::cos(theta));
      const float eta = entering ? ior : 1.0f / ior, fresnel = dielectric_fresnel(eta, wo.z);
      const int n_u = 100000;
      float3 refracted = make_float3(0, 0, 0);
      double mirrored = 0.0, rested = 0.0;
      for (int k = 0; k < n_u; ++k) {
        const DielectricSample s = dielectric_sample(wo, n, n, entering, ior, transmission, tint * transmission, rest,
                                                     (float(k) + 0.5f) / float(n_u));
        ASSERT_NE(s.event, BP_DIELECTRIC_ABSORBED);
        if (s.event == BP_DIELECTRIC_REFRACT) {
          refracted = refracted + s.factor * (1.0f / float(n_u));
          ASSERT_NEAR(dot(s.wi, refract_through(wo, n, eta)), 1.0f, 1e-6f);
        }
        if (s.event == BP_DIELECTRIC_MIRROR) {
          mirrored += s.factor.x / n_u;
          ASSERT_NEAR(dot(s.wi, make_float3(-wo.x, -wo.y, wo.z)), 1.0f, 1e-6f);
        }
        if (s.event == BP_DIELECTRIC_REST) rested += s.factor.x / n_u;
      }
      const float3 expected = tint * (transmission * (1.0f - fresnel) / (eta * eta));
      EXPECT_NEAR(refracted.x, expected.x, 1e-3f * expected.x + 1e-7f) << entering << " " << theta;
      EXPECT_NEAR(refracted.z, expected.z, 1e-3f * expected.z + 1e-7f) << entering << " " << theta;
      EXPECT_NEAR(mirrored, fresnel * transmission, 1e-3 * fresnel * transmission) << entering << " " << theta;
      EXPECT_NEAR(rested, 1.0, 1e-3) << entering << " " << theta;
      if (!entering && theta > std::asin(1.0f / ior)) {
        EXPECT_EQ(refracted.x, 0.0f);
      }
    }
}

TEST(Dielectric, AShadingNormalThatSendsTheRayToTheWrongSideAbsorbsIt) {
  // geometric normal +z, shading normal 72 degrees towards +x: straight down onto it, the mirror
  // direction 2 (n.wo) n - wo = (0.59, 0, -0.81) lies below the surface (ior 0: all mirrored)
  const float3 g = make_float3(0.0f, 0.0f, 1.0f), n = make_float3(0.951057f, 0.0f, 0.309017f);
  const float3 wo = make_float3(0.0f, 0.0f, 1.0f), white = make_float3(1, 1, 1);
  EXPECT_EQ(dielectric_sample(wo, n, g, 1, 0.0f, 1.0f, white, 0.0f, 0.5f).event, BP_DIELECTRIC_ABSORBED);
  EXPECT_EQ(dielectric_sample(wo, g, g, 1, 0.0f, 1.0f, white, 0.0f, 0.5f).event, BP_DIELECTRIC_MIRROR);
  // a ray below the shading normal's horizon finds nothing to do
  EXPECT_EQ(dielectric_sample(make_float3(-1.0f, 0.0f, 0.05f), n, g, 1, 1.5f, 1.0f, white, 0.0f, 0.5f).event,
            BP_DIELECTRIC_ABSORBED);
}

}  // namespace
}  // namespace bp

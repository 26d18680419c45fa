// A shading normal a glossy lobe can use (kernels/shared/view_normal.h, valid_reflection_normal): left alone
// where the mirror of the view about it rises above the surface; elsewhere bent toward the geometric
// normal, in the plane of the two, until that mirror is exactly min(0.9 wo.ng, 0.01) above the
// surface; so the view is always in front of it, and the bend is continuous in the view.
#include "kernels/shared/view_normal.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp {
namespace {

float3 unit(float x, float y, float z) { return normalize(make_float3(x, y, z)); }

float3 random_in_hemisphere(std::mt19937& rng, float3 n) {
  std::normal_distribution<float> g;
  for (;;) {
    const float3 v = make_float3(g(rng), g(rng), g(rng));
    const float len = length(v);
    if (len < 1e-3f) continue;
    const float3 u = v * (1.0f / len);
    if (dot(u, n) > 1e-3f) return u;
  }
}

float mirror_height(float3 ng, float3 wo, float3 n) { return dot(ng, n * (2.0f * dot(n, wo)) - wo); }

TEST(ValidReflectionNormal, LeavesANormalAloneWhereTheMirrorIsAboveTheSurface) {
  const float3 ng = unit(0, 0, 1);
  EXPECT_EQ(valid_reflection_normal(ng, unit(0.3f, 0, 1), ng).z, 1.0f);  // the flat normal
  const float3 ns = unit(0.2f, 0.1f, 1.0f), wo = unit(-0.5f, 0.2f, 1.0f);
  const float3 out = valid_reflection_normal(ng, wo, ns);
  EXPECT_EQ(out.x, ns.x);
  EXPECT_EQ(out.y, ns.y);
  EXPECT_EQ(out.z, ns.z);
}

// The smooth-shaded rim: ns tilted 60 degrees off ng, the view grazing from the other side.
TEST(ValidReflectionNormal, BendsARimNormalSoThatTheViewIsInFront) {
  const float3 ng = unit(0, 0, 1), ns = unit(std::sin(1.05f), 0, std::cos(1.05f)), wo = unit(-1.0f, 0, 0.15f);
  ASSERT_LT(dot(ns, wo), 0.0f) << "the case: the view behind the interpolated normal";
  const float3 n = valid_reflection_normal(ng, wo, ns);
  EXPECT_NEAR(length(n), 1.0f, 1e-5f);
  EXPECT_GT(dot(n, wo), 0.0f);
  EXPECT_NEAR(mirror_height(ng, wo, n), std::fmin(0.9f * dot(wo, ng), 0.01f), 1e-4f);
  EXPECT_NEAR(n.y, 0.0f, 1e-6f) << "in the plane of ns and ng";
  EXPECT_GE(n.x, 0.0f) << "toward ng from ns's side, not past it";
}

// Over random geometry: the result is unit, in front of the view, its mirror at least the threshold
// above the surface (exactly there where it bent), in the plane of ns and ng.
TEST(ValidReflectionNormal, HoldsForRandomNormalsAndViews) {
  std::mt19937 rng(7);
  int bent = 0;
  for (int i = 0; i < 20000; ++i) {
    const float3 ng = random_in_hemisphere(rng, unit(0, 0, 1));
    const float3 ns = random_in_hemisphere(rng, ng);
    const float3 wo = random_in_hemisphere(rng, ng);
    const float3 n = valid_reflection_normal(ng, wo, ns);
    const float t = std::fmin(0.9f * dot(wo, ng), 0.01f);
    ASSERT_NEAR(length(n), 1.0f, 1e-4f) << i;
    ASSERT_GT(dot(n, wo), 0.0f) << i;
    ASSERT_GE(mirror_height(ng, wo, n), t - 2e-3f) << i;
    if (n.x != ns.x || n.y != ns.y || n.z != ns.z) {
      ++bent;
      ASSERT_NEAR(mirror_height(ng, wo, n), t, 2e-3f) << i;
      ASSERT_NEAR(dot(n, cross(ns, ng)), 0.0f, 1e-3f) << i;  // in their plane
    }
  }
  EXPECT_GT(bent, 1000) << "the sweep should meet many views behind their normals";
}

// Continuous in the view: sweeping wo across the point where the bend starts moves n smoothly.
TEST(ValidReflectionNormal, IsContinuousInTheView) {
  const float3 ng = unit(0, 0, 1), ns = unit(std::sin(0.8f), 0, std::cos(0.8f));
  float3 previous = valid_reflection_normal(ng, unit(-std::sin(0.0f), 0, std::cos(0.0f)), ns);
  const float step = 0.0005f;
  for (float a = step; a < 1.5f; a += step) {
    const float3 n = valid_reflection_normal(ng, unit(-std::sin(a), 0, std::cos(a)), ns);
    EXPECT_LT(length(n - previous), 40.0f * step) << "a jump at view angle " << a;
    previous = n;
  }
}

}  // namespace
}  // namespace bp

// The optics of a thin-walled pane (kernels/shared/thin_glass.h): Schlick's Fresnel with F0 from the
// ior at its angle limits, energy (what passes plus what the mirror reflects never exceeds what
// arrives, and equals it for a white pane of transmission 1), and the event choice.
#include "kernels/shared/brdf.h"
#include "kernels/shared/thin_glass.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp {
namespace {

Material pane(float r, float g, float b, float transmission, float ior) {
  Material m{};
  m.flags = BP_MATERIAL_THIN_TRANSMITTER;
  m.transmission_tint[0] = r * transmission;
  m.transmission_tint[1] = g * transmission;
  m.transmission_tint[2] = b * transmission;
  m.transmission = transmission;
  m.ior = ior;
  return m;
}

TEST(ThinGlass, SchlickFresnelAtItsLimits) {
  EXPECT_NEAR(pane_f0(1.5f), 0.04f, 1e-7f);
  EXPECT_NEAR(pane_f0(1.0f), 0.0f, 1e-7f);
  EXPECT_NEAR(pane_f0(0.0f), 1.0f, 1e-7f);  // KHR_materials_ior's 0: all reflected
  EXPECT_NEAR(pane_fresnel(1.5f, 1.0f), 0.04f, 1e-6f);   // normal incidence: F0
  EXPECT_NEAR(pane_fresnel(1.5f, -1.0f), 0.04f, 1e-6f);  // either side
  EXPECT_NEAR(pane_fresnel(1.5f, 0.0f), 1.0f, 1e-6f);    // grazing: all reflected
  // F0 + (1 - F0)(1 - cos)^5 at 60 degrees, and F grows towards grazing
  EXPECT_NEAR(pane_fresnel(1.5f, 0.5f), 0.04f + 0.96f / 32.0f, 1e-6f);
  float previous = 0.0f;
  for (float c = 1.0f; c >= 0.0f; c -= 0.05f) {
    const float f = pane_fresnel(1.33f, c);
    EXPECT_GE(f, previous) << "cos " << c;
    EXPECT_LE(f, 1.0f);
    previous = f;
  }
}

TEST(ThinGlass, WhatPassesAndWhatTheMirrorReflectsConserveEnergy) {
  for (float c = -1.0f; c <= 1.0f; c += 0.125f) {
    const Material white = pane(1.0f, 1.0f, 1.0f, 1.0f, 1.5f);
    const PaneOptics o = pane_optics(&white, c);
    const float f = pane_fresnel(1.5f, c);
    EXPECT_NEAR(o.reflectance, f, 1e-6f);
    for (float t : {o.transmittance.x, o.transmittance.y, o.transmittance.z}) {
      EXPECT_NEAR(t, 1.0f - f, 1e-6f);
      EXPECT_NEAR(t + o.reflectance, 1.0f, 1e-6f) << "cos " << c;  // white, transmission 1: all light leaves
    }
    const Material tinted = pane(0.8f, 0.5f, 0.2f, 0.6f, 1.7f);
    const PaneOptics p = pane_optics(&tinted, c);
    const float g = pane_fresnel(1.7f, c);
    EXPECT_NEAR(p.transmittance.x, (1.0f - g) * 0.8f * 0.6f, 1e-6f);  // (1 - F) baseColor T
    EXPECT_NEAR(p.transmittance.z, (1.0f - g) * 0.2f * 0.6f, 1e-6f);
    EXPECT_NEAR(p.reflectance, g * 0.6f, 1e-6f);                      // F T
    // with the opaque rest's share 1 - T at most, nothing is created
    EXPECT_LE(p.transmittance.x + p.reflectance + (1.0f - 0.6f), 1.0f + 1e-6f);
  }
  Material opaque = pane(1.0f, 1.0f, 1.0f, 1.0f, 1.5f);
  opaque.flags = 0u;
  const PaneOptics none = pane_optics(&opaque, 1.0f);
  EXPECT_EQ(none.transmittance.x + none.transmittance.y + none.transmittance.z + none.reflectance, 0.0f);
}

TEST(ThinGlass, TheChoiceFollowsTheAlbedosAndNeverPicksAnEmptyEvent) {
  const PaneChoice c = pane_choice(make_float3(0.9f, 0.6f, 0.3f), 0.1f, 0.3f);  // pass 0.6
  EXPECT_NEAR(c.pass, 0.6f, 1e-6f);
  EXPECT_NEAR(c.mirror, 0.1f, 1e-6f);
  EXPECT_NEAR(c.rest, 0.3f, 1e-6f);
  const PaneChoice no_mirror = pane_choice(make_float3(0.5f, 0.5f, 0.5f), 0.0f, 0.0f);
  EXPECT_EQ(no_mirror.pass, 1.0f);
  EXPECT_EQ(no_mirror.mirror + no_mirror.rest, 0.0f);
  const PaneChoice black = pane_choice(make_float3(0.0f, 0.0f, 0.0f), 0.0f, 0.0f);
  EXPECT_EQ(black.pass + black.mirror + black.rest, 0.0f);
}

// A GGX transmitter's opaque rest (metallic_roughness.h): f and the continuation s are (1 - T) of the
// same material's without the pane, for any directions; the density is the same.
TEST(ThinGlass, AGgxTransmittersOpaqueRestIsItsBsdfTimesOneLessTheShare) {
  Material opaque{};
  opaque.flags = BP_MATERIAL_GGX;
  for (int c = 0; c < 3; ++c) {
    opaque.base_color[c] = 0.6f + 0.1f * float(c);
    opaque.dielectric_f0[c] = 0.04f;
  }
  opaque.metallic = 0.0f;
  opaque.roughness = 0.4f;
  opaque.specular_weight = 1.0f;
  Material glazed = opaque;
  glazed.flags |= BP_MATERIAL_THIN_TRANSMITTER;
  glazed.transmission = 0.75f;
  const Bsdf a = bsdf_from_material(&opaque), b = bsdf_from_material(&glazed);
  EXPECT_NEAR(b.continuation, 0.25f * a.continuation, 1e-6f);
  const float3 n = make_float3(0.0f, 0.0f, 1.0f), wo = normalize(make_float3(0.3f, 0.1f, 0.9f));
  for (const float3 wi : {normalize(make_float3(-0.3f, -0.1f, 0.9f)), normalize(make_float3(0.5f, -0.4f, 0.3f))}) {
    const BsdfValue va = bsdf_evaluate(&a, n, wi, wo), vb = bsdf_evaluate(&b, n, wi, wo);
    ASSERT_GT(va.f.x, 0.0f);
    EXPECT_NEAR(vb.f.x, 0.25f * va.f.x, 1e-6f * va.f.x);
    EXPECT_NEAR(vb.f.z, 0.25f * va.f.z, 1e-6f * va.f.z);
    EXPECT_FLOAT_EQ(vb.pdf_uv, va.pdf_uv);
  }
}

}  // namespace
}  // namespace bp

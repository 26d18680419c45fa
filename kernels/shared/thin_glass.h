// The optics of a thin-walled transmitter (glTF KHR_materials_transmission without a volume, or with
// thickness 0; docs/design.md §11): a pane that passes light straight through, attenuated, and reflects
// the rest as a mirror. Fresnel is Schlick's approximation with F0 from the ior, as glTF's
// fresnel_mix (Appendix B, KHR_materials_ior) evaluates it for both the BRDF and the BTDF, so a pane
// here looks as it does in glTF viewers. A material is the mix (1 - T) opaque rest + T pane
// (types.h: kd and ks are the rest's, scaled at load).
#ifndef BP_SHARED_THIN_GLASS_H
#define BP_SHARED_THIN_GLASS_H
#include "shared/compat.h"
#include "shared/types.h"

// F0 = ((ior - 1) / (ior + 1))^2   (KHR_materials_ior; 1.5 gives 0.04, ior 0 gives 1: all reflected)
BP_FN float pane_f0(float ior) {
  float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

// Schlick: F = F0 + (1 - F0) (1 - |cos theta|)^5, theta the angle between the ray and the pane's normal.
BP_FN float pane_fresnel(float ior, float cos_theta) {
  float f0 = pane_f0(ior);
  float m = 1.0f - fmin(fabs(cos_theta), 1.0f);
  float m2 = m * m;
  return f0 + (1.0f - f0) * (m2 * m2 * m);
}

typedef struct {
  float3 transmittance;  // straight through: (1 - F) baseColor T   (glTF fresnel_mix of the specular BTDF)
  float reflectance;     // the mirror: F T                          (glTF fresnel_mix of the specular BRDF)
} PaneOptics;

// The pane of a material hit at cos_theta (either side); zero for an opaque material.
BP_FN PaneOptics pane_optics(BP_GLOBAL const Material* m, float cos_theta) {
  PaneOptics o;
  o.transmittance = make_float3(0.0f, 0.0f, 0.0f);
  o.reflectance = 0.0f;
  if (!BP_FEATURE_TRANSMISSION || !(m->flags & BP_MATERIAL_THIN_TRANSMITTER)) return o;
  float f = pane_fresnel(m->ior, cos_theta);
  o.transmittance = bp_load3(m->transmission_tint) * (1.0f - f);  // tint = baseColor T (types.h)
  o.reflectance = f * m->transmission;
  return o;
}

// What a path does at a pane hit, chosen by albedo: pass straight through, the mirror, or the opaque
// rest (an ordinary vertex with the scaled BSDF). The choice is no vertex of the weights: a passing
// path is the path without the pane, and its factor / probability keeps PT's estimate unbiased.
#define BP_PANE_PASS 0u
#define BP_PANE_MIRROR 1u
#define BP_PANE_REST 2u

typedef struct {
  float pass;    // probabilities of the three events, summing to 1 (all 0 where nothing leaves the pane)
  float mirror;
  float rest;
} PaneChoice;

// With mirror_albedo 0 the mirror is never chosen (RB's eye rays: the mirror is PT's alone).
// rest_albedo: the rest's reflectance on the side hit (0 behind a single-sided surface).
BP_FN PaneChoice pane_choice(float3 transmittance, float mirror_albedo, float rest_albedo) {
  float pass = (transmittance.x + transmittance.y + transmittance.z) * (1.0f / 3.0f);
  float sum = pass + mirror_albedo + rest_albedo;
  PaneChoice c;
  c.pass = sum > 0.0f ? pass / sum : 0.0f;
  c.mirror = sum > 0.0f ? mirror_albedo / sum : 0.0f;
  c.rest = sum > 0.0f ? rest_albedo / sum : 0.0f;
  return c;
}

#endif  // BP_SHARED_THIN_GLASS_H

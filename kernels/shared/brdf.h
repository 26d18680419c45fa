// The BSDF of a vertex, one of two models chosen per material (docs/design.md §6, §11): Modified Phong
// (extras.phong, Lambert) here, or with BP_MATERIAL_GGX glTF's metallic-roughness BRDF
// (shared/metallic_roughness.h); with their sampling routines and pdfs.
// Conventions: wo points from the vertex towards the eye side, wi towards the light side; both
// unit and away from the surface; n is the normal on the side of wo. Every pdf here is in the
// paper's uv measure (eq. 7): pdf_uv = 2 pi * pdf_solid_angle.
#ifndef BP_SHARED_BRDF_H
#define BP_SHARED_BRDF_H
#include "shared/compat.h"
#include "shared/frame.h"
#include "shared/metallic_roughness.h"
#include "shared/types.h"
#include "shared/view_normal.h"

typedef struct {
  float3 kd;
  float3 ks;
  float3 emission;
  float shininess;      // of the density (every weight input): the material's, or the patch's mean with textures
  float shininess_f;    // of f: the texel's with textures (textured.h), else the same
  float p_diffuse;      // probability of sampling the diffuse lobe (by albedo)
  float continuation;   // Russian-roulette continuation probability s (material only, docs/design.md §3)
  bp_u32 flags;
  MetallicRoughness metallic_roughness;  // BP_MATERIAL_GGX: the glTF model (kd, ks, shininess, p_diffuse unused)
} Bsdf;

// Whether b is glTF's metallic-roughness model (else Modified Phong).
BP_FN int bsdf_is_ggx(const Bsdf* b) { return BP_FEATURE_GGX && (b->flags & BP_MATERIAL_GGX) != 0u; }

// The lobe choice and the continuation probability depend on the material alone, so the RB side
// (which never sees PT's throughput) evaluates the same numbers (docs/design.md §3, condition 1).
BP_FN Bsdf bsdf_from_material(BP_GLOBAL const Material* m) {
  Bsdf b;
  b.kd = bp_load3(m->kd);
  b.ks = bp_load3(m->ks);
  b.emission = bp_load3(m->emission);
  b.shininess = m->shininess;
  b.shininess_f = m->shininess;
  b.flags = m->flags;
  if (bsdf_is_ggx(&b)) {
    b.metallic_roughness = metallic_roughness_from_material(m);
    b.p_diffuse = 0.0f;  // the lobe choice depends on wo here (metallic_roughness_specular_probability)
    b.continuation = metallic_roughness_continuation(&b.metallic_roughness);
    return b;
  }
  float albedo_d = bp_max3(b.kd), albedo_s = bp_max3(b.ks);
  float albedo = albedo_d + albedo_s;
  b.p_diffuse = albedo > 0.0f && BP_FEATURE_PHONG ? albedo_d / albedo : 1.0f;  // Lambert-only build: 1
  b.continuation = clamp(bp_max3(b.kd + b.ks), 0.0f, 1.0f);
  return b;
}

// cos^n for cos in (0, 1] and n >= 0, as exp2(n log2(cos)). PoCL's pow() covers every special case
// and made the Phong lobe the costliest part of both kernels; this is as precise as the float cos
// it is given allows (an error dc moves cos^n by n dc / cos either way).
BP_FN float pow_unit(float cos_angle, float n) { return exp2(n * log2(cos_angle)); }

// Diffuse lobe, cosine-weighted: pdf_uv = 2 cos(theta)   (paper §5.2).
BP_FN float pdf_uv_cosine(float cos_theta) { return cos_theta > 0.0f ? 2.0f * cos_theta : 0.0f; }

// The BRDF and the PT density of one pair of directions, which share the lobe's cos^n (the costliest
// thing in either): callers that need both (a weight beside a reflection) evaluate it once.
typedef struct {
  float3 f;      // f(wi, wo) in sr^-1: kd/pi + ks (n+2)/(2 pi) cos^n alpha, alpha between wi and the mirror of wo
  float pdf_uv;  // the PT density of wi given wo: the full lobe mixture, whichever lobe was sampled (docs/design.md §2)
} BsdfValue;

BP_FN BsdfValue bsdf_evaluate(const Bsdf* b, float3 n, float3 wi, float3 wo) {
  BsdfValue v;
  v.f = make_float3(0.0f, 0.0f, 0.0f);
  v.pdf_uv = 0.0f;
  float cos_theta = dot(n, wi);
  if (cos_theta <= 0.0f) return v;
  if (bsdf_is_ggx(b)) {
    metallic_roughness_evaluate(&b->metallic_roughness, n, wi, wo, &v.f, &v.pdf_uv);
    return v;
  }
  const int front = dot(n, wo) > 0.0f;
  // Lambert's term does not depend on the view: a viewer behind an interpolated normal still sees
  // the light it receives, as in Cycles (bsdf_shading_normal)
  v.f = b->kd * BP_INV_PI;
  if (!BP_FEATURE_PHONG || b->p_diffuse >= 1.0f) {  // Lambert: no cos^n
    v.pdf_uv = pdf_uv_cosine(cos_theta);
    return v;
  }
  float cos_alpha = dot(reflect_about(wo, n), wi);  // the lobe is zero beyond 90 degrees, also for n = 0
  float lobe = cos_alpha > 0.0f ? pow_unit(fmin(cos_alpha, 1.0f), b->shininess) : 0.0f;
  float lobe_f = lobe;  // a textured hit's own exponent for f; its patch's for the density
  if (BP_FEATURE_TEXTURES && b->shininess_f != b->shininess)
    lobe_f = cos_alpha > 0.0f ? pow_unit(fmin(cos_alpha, 1.0f), b->shininess_f) : 0.0f;
  if (front) v.f += b->ks * ((b->shininess_f + 2.0f) * (0.5f * BP_INV_PI) * lobe_f);
  // Phong lobe around the mirror direction: pdf_uv = (n+1) cos^n(alpha)   (docs/design.md §2)
  v.pdf_uv = b->p_diffuse * pdf_uv_cosine(cos_theta) + (1.0f - b->p_diffuse) * ((b->shininess + 1.0f) * lobe);
  return v;
}

// The shading normal the BSDF evaluates and samples with at a vertex seen from wo (ng: the flat
// normal on wo's side, ns the interpolated or mapped one). A Lambert surface keeps ns: its term does
// not depend on the view (bsdf_evaluate). A surface with a lobe around the mirror direction (Phong's,
// glTF's GGX layer) gets ns bent until the mirror of wo is above the surface (valid_reflection_normal),
// so the viewer is in front of it: Cycles bends its glossy closures' normals so; here the whole
// BSDF, diffuse base included, evaluates about the bent normal. Both estimators call this with the
// same ng, wo and ns at the eye vertex, so they reflect alike.
BP_FN float3 bsdf_shading_normal(const Bsdf* b, float3 ng, float3 wo, float3 ns) {
  const int lambert = !bsdf_is_ggx(b) && (!BP_FEATURE_PHONG || b->p_diffuse >= 1.0f);
  return lambert ? ns : valid_reflection_normal(ng, wo, ns);
}

BP_FN float3 bsdf_eval(const Bsdf* b, float3 n, float3 wi, float3 wo) { return bsdf_evaluate(b, n, wi, wo).f; }
BP_FN float bsdf_pdf_uv(const Bsdf* b, float3 n, float3 wi, float3 wo) { return bsdf_evaluate(b, n, wi, wo).pdf_uv; }

// Cosine-weighted direction about +z of a local frame.
BP_FN float3 sample_cosine_local(float u1, float u2) {
  float r = sqrt(u1), phi = BP_TWO_PI * u2;
  return make_float3(r * cos(phi), r * sin(phi), sqrt(fmax(0.0f, 1.0f - u1)));
}

// Direction with density (n+1)/(2 pi) cos^n(alpha) about +z. sin^2 alpha is computed as
// -expm1(2 ln(u)/(n+1)) so lobes of shininess 1e6 keep their width in float.
BP_FN float3 sample_phong_lobe_local(float u1, float u2, float shininess) {
  float log_cos = log(fmax(1.0f - u1, 1e-30f)) / (shininess + 1.0f);  // cos alpha = (1-u1)^(1/(n+1))
  float cos_alpha = exp(log_cos);
  float sin_alpha = sqrt(fmax(0.0f, -expm1(2.0f * log_cos)));
  float phi = BP_TWO_PI * u2;
  return make_float3(sin_alpha * cos(phi), sin_alpha * sin(phi), cos_alpha);
}

typedef struct {
  float3 wi;
  float pdf_uv;   // mixture density of wi (0: the sample fell below the surface; end the path)
  float3 f;       // f(wi, wo)
} BsdfSample;

BP_FN BsdfSample bsdf_sample(const Bsdf* b, float3 n, float3 wo, float u_lobe, float u1, float u2) {
  BsdfSample s;
  if (bsdf_is_ggx(b)) {
    const MetallicRoughness* mr = &b->metallic_roughness;
    if (u_lobe < metallic_roughness_specular_probability(mr, dot(n, wo))) {
      s.wi = ggx_sample_reflection(mr->density_alpha, n, wo, u1, u2);
    } else {
      Frame f = frame_from_normal(n);
      s.wi = frame_to_world(&f, sample_cosine_local(u1, u2));
    }
  } else if (u_lobe < b->p_diffuse) {
    Frame f = frame_from_normal(n);
    s.wi = frame_to_world(&f, sample_cosine_local(u1, u2));
  } else {
    Frame f = frame_from_normal(reflect_about(wo, n));
    s.wi = frame_to_world(&f, sample_phong_lobe_local(u1, u2, b->shininess));
  }
  BsdfValue v = bsdf_evaluate(b, n, s.wi, wo);
  s.pdf_uv = v.pdf_uv;
  s.f = v.f;
  return s;
}

#endif  // BP_SHARED_BRDF_H

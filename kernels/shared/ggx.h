// The Trowbridge-Reitz (GGX) microfacet distribution as glTF 2.0's Appendix B writes its specular_brdf
// (D_GGX, the height-correlated Smith V_GGX), and its sampling by visible normals (Heitz, "Sampling the
// GGX Distribution of Visible Normals", JCGT 7(4), 2018). Angles are about the surface normal n; h is
// the half vector of wi and wo. Every function takes the cosines it needs, so the same numbers come out
// in the kernels and in the host tests.
#ifndef BP_SHARED_GGX_H
#define BP_SHARED_GGX_H
#include "shared/compat.h"
#include "shared/frame.h"

// The smallest alpha: below it a float lobe is narrower than the directions float can tell apart near
// the mirror (D's peak 1/(pi alpha^2) passes 3e5 here), so roughness 0 is this sharp lobe, not a delta.
#define BP_GGX_MIN_ALPHA 1.0e-3f

// alpha = roughness^2 (glTF 2.0 Appendix B, specular_brdf(alpha = roughness^2)), at least BP_GGX_MIN_ALPHA.
BP_FN float ggx_alpha_from_roughness(float roughness) {
  return fmax(roughness * roughness, BP_GGX_MIN_ALPHA);
}

// D(h) = alpha^2 chi+(n.h) / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2)   (glTF 2.0 Appendix B, D_GGX),
// written with sin^2 = 1 - cos^2 passed in so that a lobe of alpha 1e-3 keeps its shape in float:
// (n.h)^2 (alpha^2 - 1) + 1 = alpha^2 cos^2 + sin^2.
BP_FN float ggx_d(float alpha, float cos_h, float sin2_h) {
  if (!(cos_h > 0.0f)) return 0.0f;
  float a2 = alpha * alpha;
  float t = a2 * cos_h * cos_h + sin2_h;
  return a2 / (BP_PI * t * t);
}

// sqrt(alpha^2 + (1 - alpha^2) cos^2): the term each direction brings to Smith's masking (glTF 2.0
// Appendix B, V_GGX); 1 + Lambda(w) = (cos + this) / (2 cos)   (Heitz 2014, eq. 72 with 86).
BP_FN float ggx_smith_term(float alpha, float cos_theta) {
  float a2 = alpha * alpha;
  return sqrt(fmax(a2 + (1.0f - a2) * cos_theta * cos_theta, 0.0f));
}

// V = G2 / (4 |n.wi| |n.wo|) with the height-correlated G2 = 1 / (1 + Lambda(wi) + Lambda(wo)):
//   V = 0.5 / (n.wi sqrt(alpha^2 + (1 - alpha^2)(n.wo)^2) + n.wo sqrt(alpha^2 + (1 - alpha^2)(n.wi)^2))
// (glTF 2.0 Appendix B, V_GGX, height-correlated; Heitz 2014, eq. 99).
BP_FN float ggx_v(float alpha, float cos_i, float cos_o) {
  if (!(cos_i > 0.0f) || !(cos_o > 0.0f)) return 0.0f;
  return 0.5f / (cos_i * ggx_smith_term(alpha, cos_o) + cos_o * ggx_smith_term(alpha, cos_i));
}

// The Smith masking of one direction, G1(w) = 1 / (1 + Lambda(w)) = 2 cos / (cos + sqrt(alpha^2 + (1 -
// alpha^2) cos^2))   (Heitz 2014, eq. 43 with 86).
BP_FN float ggx_g1(float alpha, float cos_theta) {
  if (!(cos_theta > 0.0f)) return 0.0f;
  return 2.0f * cos_theta / (cos_theta + ggx_smith_term(alpha, cos_theta));
}

// Density (uv measure) of wi = reflect(wo, h) when h is drawn from the visible normals of wo:
//   p(wi) = D_wo(h) / (4 wo.h),  D_wo(h) = G1(wo) max(0, wo.h) D(h) / (n.wo)   (Heitz 2018, eq. 1 and 17)
//   p(wi) = G1(wo) D(h) / (4 n.wo) = D(h) / (2 (n.wo + sqrt(alpha^2 + (1 - alpha^2)(n.wo)^2)))
// times 2 pi for the uv measure (eq. 7). Defined for every wi (also below the surface, where the caller
// sees that the lobe's sample is lost); zero when wo is not above the surface.
BP_FN float ggx_vndf_reflection_pdf_uv(float alpha, float cos_o, float cos_h, float sin2_h) {
  if (!(cos_o > 0.0f)) return 0.0f;
  return BP_PI * ggx_d(alpha, cos_h, sin2_h) / (cos_o + ggx_smith_term(alpha, cos_o));
}

// The largest ggx_vndf_reflection_pdf_uv over every pair of directions: D <= 1/(pi alpha^2) and
// n.wo + sqrt(...) >= alpha, so p_uv <= 1/alpha^3 (approached by grazing wo and its mirror).
BP_FN float ggx_vndf_peak_pdf_uv(float alpha) { return 1.0f / (alpha * alpha * alpha); }

// A microfacet normal drawn from the visible normals of wo (both in the local frame of n = +z, wo
// above it), from two uniform numbers: wo stretched to the hemisphere configuration, a point of the
// projected disk (the half-disk in front of it squeezed by (1 + wo_h.z)/2), lifted to the hemisphere
// and unstretched   (Heitz 2018, Listing 1).
BP_FN float3 ggx_sample_visible_normal_local(float alpha, float3 wo, float u1, float u2) {
  float3 vh = normalize(make_float3(alpha * wo.x, alpha * wo.y, wo.z));
  float len2 = vh.x * vh.x + vh.y * vh.y;
  float3 t1 = len2 > 0.0f ? make_float3(-vh.y, vh.x, 0.0f) * (1.0f / sqrt(len2)) : make_float3(1.0f, 0.0f, 0.0f);
  float3 t2 = cross(vh, t1);
  float r = sqrt(u1), phi = BP_TWO_PI * u2;
  float p1 = r * cos(phi), p2 = r * sin(phi);
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * p2;
  float3 nh = t1 * p1 + t2 * p2 + vh * sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize(make_float3(alpha * nh.x, alpha * nh.y, fmax(1.0e-7f, nh.z)));
}

// The direction reflected about a visible normal of wo (world space, about the normal n): the GGX
// lobe's sample, with density ggx_vndf_reflection_pdf_uv. It may fall below the surface.
BP_FN float3 ggx_sample_reflection(float alpha, float3 n, float3 wo, float u1, float u2) {
  Frame f = frame_from_normal(n);
  float3 wo_local = make_float3(dot(wo, f.t), dot(wo, f.b), dot(wo, f.n));
  float3 h = frame_to_world(&f, ggx_sample_visible_normal_local(alpha, wo_local, u1, u2));
  return reflect_about(wo, h);
}

// Schlick's weight (1 - cos)^5 of the Fresnel term F = f0 + (f90 - f0)(1 - |v.h|)^5 (glTF 2.0 Appendix B).
BP_FN float schlick_weight(float cos_vh) {
  float m = clamp(1.0f - cos_vh, 0.0f, 1.0f);
  float m2 = m * m;
  return m2 * m2 * m;
}

#endif  // BP_SHARED_GGX_H

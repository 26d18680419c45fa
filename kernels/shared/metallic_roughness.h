// glTF 2.0's metallic-roughness BRDF as the specification's Appendix B writes it, with KHR_materials_ior
// and KHR_materials_specular (docs/design.md §11):
//   material   = mix(dielectric_brdf, metal_brdf, metallic)
//   metal_brdf = conductor_fresnel(f0 = baseColor, specular_brdf(alpha = roughness^2))
//   dielectric_brdf = fresnel_mix(f0_color = specularColor, ior, weight = specular,
//                                 base = diffuse_brdf(baseColor), layer = specular_brdf(alpha))
// with Lambert's diffuse_brdf, GGX's specular_brdf (shared/ggx.h) and Schlick's Fresnel of v.h.
// Sampling: the diffuse lobe by cosine, the specular one by GGX's visible normals, the lobe chosen by
// a Fresnel-aware albedo estimate of the material, the normal and wo alone. Every pdf is in the
// paper's uv measure (eq. 7). The `density_*` fields are the weight inputs: the material's, or with
// textures its patch's mean (docs/design.md §6), while f reads the texel's.
#ifndef BP_SHARED_METALLIC_ROUGHNESS_H
#define BP_SHARED_METALLIC_ROUGHNESS_H
#include "shared/compat.h"
#include "shared/ggx.h"
#include "shared/types.h"

typedef struct {
  float3 base_color;      // of f
  float3 dielectric_f0;   // min(((ior - 1)/(ior + 1))^2 specularColor, 1)
  float metallic;         // of f
  float specular_weight;  // KHR_materials_specular's specular (the dielectric's f0 and f90 scale)
  float alpha;            // GGX alpha of f
  float density_alpha;    // GGX alpha of the density and of every weight input
  float density_base_max; // max(r, g, b) of the base colour, for the lobe choice and s
  float density_metallic;
  float density_f0_max;   // max(dielectric_f0) and specular of the density and every weight input
  float density_specular_weight;
  float opaque;           // 1 - transmission: the opaque rest's share of a transmitter (docs/design.md §11), else 1
} MetallicRoughness;

BP_FN MetallicRoughness metallic_roughness_from_material(BP_GLOBAL const Material* m) {
  MetallicRoughness mr;
  mr.base_color = bp_load3(m->base_color);
  mr.dielectric_f0 = bp_load3(m->dielectric_f0);
  mr.metallic = m->metallic;
  mr.specular_weight = m->specular_weight;
  mr.alpha = ggx_alpha_from_roughness(m->roughness);
  mr.density_alpha = mr.alpha;
  mr.density_base_max = bp_max3(mr.base_color);
  mr.density_metallic = m->metallic;
  mr.density_f0_max = bp_max3(mr.dielectric_f0);
  mr.density_specular_weight = mr.specular_weight;
  mr.opaque = (m->flags & (BP_MATERIAL_THIN_TRANSMITTER | BP_MATERIAL_REFRACTOR)) ? 1.0f - m->transmission : 1.0f;
  return mr;
}

// Schlick's F = f0 + (1 - f0) w for a scalar f0 and Schlick's weight w = (1 - cos)^5.
BP_FN float schlick_scalar(float f0, float weight) { return f0 + (1.0f - f0) * weight; }

// The albedos the lobe choice compares, from Schlick's Fresnel at n.wo (standing in for v.h): the
// specular lobe's w F_dielectric + metallic F_metal, the diffuse lobe's (1 - metallic)(1 - w
// max(F_dielectric)) max(base); both patch-level. Returns P(specular lobe | wo).
BP_FN float metallic_roughness_specular_probability(const MetallicRoughness* mr, float cos_o) {
  float weight = schlick_weight(clamp(cos_o, 0.0f, 1.0f));
  float f_dielectric = mr->density_specular_weight * schlick_scalar(mr->density_f0_max, weight);
  float f_metal = schlick_scalar(mr->density_base_max, weight);
  float m = mr->density_metallic;
  float specular = (1.0f - m) * f_dielectric + m * f_metal;
  float diffuse = (1.0f - m) * (1.0f - f_dielectric) * mr->density_base_max;
  float total = specular + diffuse;
  return total > 0.0f ? specular / total : 0.0f;
}

// The continuation probability s (docs/design.md §3: of the material alone): the albedo with Schlick's F
// averaged over a cosine-weighted hemisphere, F0 + (1 - F0)/21 (since the integral of 2 mu (1 - mu)^5
// over [0, 1] is 1/21). Positive wherever f can be.
BP_FN float metallic_roughness_continuation(const MetallicRoughness* mr) {
  const float mean_weight = 1.0f / 21.0f;
  float f_dielectric = mr->density_specular_weight * schlick_scalar(mr->density_f0_max, mean_weight);
  float f_metal = schlick_scalar(mr->density_base_max, mean_weight);
  float m = mr->density_metallic;
  float albedo = (1.0f - m) * (f_dielectric + (1.0f - f_dielectric) * mr->density_base_max) + m * f_metal;
  return clamp(mr->opaque * albedo, 0.0f, 1.0f);  // a thin transmitter's opaque rest: (1 - T) of it
}

// f(wi, wo) and the PT density pdf_uv(wi | wo) of the lobe mixture about n (0 for wi below n).
BP_FN void metallic_roughness_evaluate(const MetallicRoughness* mr, float3 n, float3 wi, float3 wo, float3* f,
                                       float* pdf_uv) {
  *f = make_float3(0.0f, 0.0f, 0.0f);
  *pdf_uv = 0.0f;
  float cos_i = dot(n, wi), cos_o = dot(n, wo);
  if (!(cos_i > 0.0f)) return;
  float3 h = wi + wo;
  float h_len = length(h);
  if (!(h_len > 0.0f)) return;
  h = h * (1.0f / h_len);
  float cos_h = dot(n, h);
  float3 nxh = cross(n, h);
  float sin2_h = dot(nxh, nxh);
  float p_specular = metallic_roughness_specular_probability(mr, cos_o);
  // diffuse by cosine: 2 cos(theta) (paper §5.2); specular by visible normals (shared/ggx.h)
  *pdf_uv = (1.0f - p_specular) * 2.0f * cos_i +
            (p_specular > 0.0f ? p_specular * ggx_vndf_reflection_pdf_uv(mr->density_alpha, cos_o, cos_h, sin2_h) : 0.0f);
  if (!(cos_o > 0.0f)) return;
  float weight = schlick_weight(dot(wo, h));  // (1 - |v.h|)^5
  // specular_brdf = V_GGX D_GGX   (glTF 2.0 Appendix B)
  float specular = ggx_v(mr->alpha, cos_i, cos_o) * ggx_d(mr->alpha, cos_h, sin2_h);
  // KHR_materials_specular: dielectric_fresnel = specular (f0 + (1 - f0)(1 - |v.h|)^5)
  float3 one = make_float3(1.0f, 1.0f, 1.0f);
  float3 f_dielectric = (mr->dielectric_f0 + (one - mr->dielectric_f0) * weight) * mr->specular_weight;
  // dielectric_brdf = dielectric_fresnel specular_brdf + (1 - max(dielectric_fresnel)) diffuse_brdf
  float3 dielectric = f_dielectric * specular + mr->base_color * ((1.0f - bp_max3(f_dielectric)) * BP_INV_PI);
  // metal_brdf = conductor_fresnel: (baseColor + (1 - baseColor)(1 - |v.h|)^5) specular_brdf
  float3 metal = (mr->base_color + (one - mr->base_color) * weight) * specular;
  // material = mix(dielectric_brdf, metal_brdf, metallic), times the opaque rest's share (docs/design.md §11)
  *f = (dielectric * (1.0f - mr->metallic) + metal * mr->metallic) * mr->opaque;
}

// The view-independent stand-in for PT's s p_b at the eye vertex (weights.h): no wo, so an upper bound
// over every view -- the diffuse lobe's probability at its largest (n.wo = 1) times 2 cos(theta_in),
// and the specular lobe's at its largest (grazing wo) times the GGX lobe's peak density 1/alpha^3.
BP_FN float metallic_roughness_eye_proxy_pdf_uv(const MetallicRoughness* mr, float continuation, float cos_theta_in) {
  float p_diffuse_max = 1.0f - metallic_roughness_specular_probability(mr, 1.0f);
  float p_specular_max = metallic_roughness_specular_probability(mr, 0.0f);
  return continuation * (p_diffuse_max * 2.0f * cos_theta_in + p_specular_max * ggx_vndf_peak_pdf_uv(mr->density_alpha));
}

#endif  // BP_SHARED_METALLIC_ROUGHNESS_H

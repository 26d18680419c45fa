// The optics of a refracting dielectric (glTF KHR_materials_transmission with KHR_materials_volume,
// thickness > 0; docs/design.md §11): a smooth interface between air and a homogeneous medium that
// refracts by Snell's law and reflects by the exact dielectric Fresnel equations, and the medium's
// Beer-Lambert attenuation (KHR_materials_volume's attenuationColor over attenuationDistance). As a
// thin pane's, the surface is the mix (1 - T) opaque rest + T interface; its transmitted light is
// tinted by baseColor at each crossing (glTF's specular_btdf times baseColor). Both events are delta
// vertices, PT's alone; RB sees only the rest (a refracting surface is opaque to bundles).
#ifndef BP_SHARED_DIELECTRIC_H
#define BP_SHARED_DIELECTRIC_H
#include "shared/compat.h"
#include "shared/frame.h"
#include "shared/types.h"

// Fresnel reflectance of unpolarised light at a smooth interface, cos_i > 0 on the incident side,
// eta = n_t / n_i (the far side's index over the near side's). 1 past the critical angle.
//   r_s = (cos_i - eta cos_t) / (cos_i + eta cos_t),  r_p = (eta cos_i - cos_t) / (eta cos_i + cos_t),
//   F = (r_s^2 + r_p^2) / 2,  sin_t = sin_i / eta   (Snell)
BP_FN float dielectric_fresnel(float eta, float cos_i) {
  cos_i = fmin(fmax(cos_i, 0.0f), 1.0f);
  float sin_t2 = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin_t2 >= 1.0f) return 1.0f;  // total internal reflection
  float cos_t = sqrt(1.0f - sin_t2);
  float r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  float r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (r_s * r_s + r_p * r_p);
}

// The refracted direction of wo (pointing away from the surface on n's side, cos_i = n.wo > 0) into
// the far side, eta = n_t / n_i; the caller has checked that it is not totally reflected.
//   wt = -wo / eta + (cos_i / eta - cos_t) n
BP_FN float3 refract_through(float3 wo, float3 n, float eta) {
  float cos_i = dot(n, wo);
  float sin_t2 = fmax(0.0f, (1.0f - cos_i * cos_i) / (eta * eta));
  float cos_t = sqrt(fmax(0.0f, 1.0f - sin_t2));
  return normalize(-wo / eta + n * (cos_i / eta - cos_t));
}

// Beer-Lambert transmittance over `distance` metres of a medium with attenuation coefficient sigma
// (m^-1): exp(-sigma d). 1 where sigma is 0, also over an unbounded distance.
BP_FN float3 medium_transmittance(float3 sigma, float distance) {
  return make_float3(sigma.x > 0.0f ? exp(-sigma.x * distance) : 1.0f, sigma.y > 0.0f ? exp(-sigma.y * distance) : 1.0f,
                     sigma.z > 0.0f ? exp(-sigma.z * distance) : 1.0f);
}

#define BP_DIELECTRIC_REFRACT 0u
#define BP_DIELECTRIC_MIRROR 1u
#define BP_DIELECTRIC_REST 2u
#define BP_DIELECTRIC_ABSORBED 3u  // nothing leaves, or the shading normal sent the ray to the wrong side

typedef struct {
  bp_u32 event;   // BP_DIELECTRIC_*
  float3 wi;      // the new direction (refract, mirror)
  float3 factor;  // what the throughput is multiplied by: the event's weight over its probability
} DielectricSample;

// What a path does where it meets a refracting material, coming along -wo: refract, reflect, or stop
// at the opaque rest, chosen in proportion to their albedos (u uniform in [0, 1)).
//   shading, geometric: the normals on wo's side (surface.h); entering: wo is on the front side;
//   ior: the medium's index (air outside is 1; 0 reflects everything, as KHR_materials_ior says);
//   transmission T, tint = baseColor T; rest_albedo: the rest's reflectance on wo's side.
// Refracted: (1 - F) tint (n_i / n_t)^2, the last factor radiance's change of solid angle across the
// interface (it cancels over a closed object). Reflected: F T.
BP_FN DielectricSample dielectric_sample(float3 wo, float3 shading, float3 geometric, int entering, float ior,
                                         float transmission, float3 tint, float rest_albedo, float u) {
  DielectricSample s;
  s.event = BP_DIELECTRIC_ABSORBED;
  s.wi = wo;
  s.factor = make_float3(0.0f, 0.0f, 0.0f);
  float cos_i = dot(shading, wo);
  if (!(cos_i > 0.0f)) return s;
  float eta = ior < 1.0f ? 0.0f : (entering ? ior : 1.0f / ior);
  float fresnel = eta > 0.0f ? dielectric_fresnel(eta, cos_i) : 1.0f;
  float3 refracted = tint * (1.0f - fresnel);
  float p_refract = (refracted.x + refracted.y + refracted.z) * (1.0f / 3.0f);
  float p_mirror = fresnel * transmission;
  float sum = p_refract + p_mirror + rest_albedo;
  if (!(sum > 0.0f)) return s;
  u *= sum;
  if (p_refract > 0.0f && u < p_refract) {
    s.wi = refract_through(wo, shading, eta);
    if (!(dot(geometric, s.wi) < 0.0f)) return s;  // the shading normal's trap (docs/design.md §6)
    s.event = BP_DIELECTRIC_REFRACT;
    s.factor = refracted * (sum / (p_refract * eta * eta));
  } else if (p_mirror > 0.0f && u < p_refract + p_mirror) {
    s.wi = reflect_about(wo, shading);
    if (!(dot(geometric, s.wi) > 0.0f)) return s;
    s.event = BP_DIELECTRIC_MIRROR;
    s.factor = make_float3(1.0f, 1.0f, 1.0f) * sum;  // F T / P(mirror), P(mirror) = F T / sum
  } else if (rest_albedo > 0.0f) {
    s.event = BP_DIELECTRIC_REST;
    s.factor = make_float3(1.0f, 1.0f, 1.0f) * (sum / rest_albedo);  // 1 / P(rest): the rest's BSDF follows
  }
  return s;
}

#endif  // BP_SHARED_DIELECTRIC_H

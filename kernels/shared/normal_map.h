// glTF's normalTexture (DESIGN.md §6): a tangent-space normal per texel, turned into the world by
// the frame of the interpolated normal N, the interpolated TANGENT T and its handedness w. Only the
// shading normal changes: the flat normal stays the geometric one and every weight input patch-level.
#ifndef BP_SHARED_NORMAL_MAP_H
#define BP_SHARED_NORMAL_MAP_H
#include "shared/compat.h"
#include "shared/texture.h"

// The tangent-space normal of a (linear) texel: n_ts = normalize((2 rgb - 1) (scale, scale, 1)) (glTF
// 2.0, material.normalTexture). A texel of length 0 after scaling gives +z, the unperturbed normal.
BP_FN float3 normal_map_tangent_space(Texel t, float scale) {
  float3 n = make_float3((2.0f * t.r - 1.0f) * scale, (2.0f * t.g - 1.0f) * scale, 2.0f * t.b - 1.0f);
  float len = length(n);
  return len > 0.0f ? n / len : make_float3(0.0f, 0.0f, 1.0f);
}

// n_ts in the frame of unit normal n and tangent t (not yet orthogonal to n) of handedness w:
// T = normalize(t - n (n.t)) (Gram-Schmidt), B = w cross(n, T), N' = normalize(x T + y B + z n).
// Where t is (nearly) parallel to n there is no frame: n itself.
BP_FN float3 normal_map_to_world(float3 n, float3 t, float w, float3 n_ts) {
  float3 tangent = t - n * dot(n, t);  // Gram-Schmidt against the interpolated normal
  float len = length(tangent);
  if (!(len > 1e-6f)) return n;
  tangent = tangent / len;
  float3 bitangent = cross(n, tangent) * (w < 0.0f ? -1.0f : 1.0f);  // B = w cross(N, T)
  float3 mapped = tangent * n_ts.x + bitangent * n_ts.y + n * n_ts.z;
  float mapped_len = length(mapped);
  return mapped_len > 0.0f ? mapped / mapped_len : n;
}

// The shading normal at barycentrics (b1, b2) of `triangle` of `material` with its normal map:
// `interpolated` (the NORMAL-based shading normal on the ray's side, shading_normal_at) perturbed by
// the texel, the corners' TANGENT (12 floats per triangle: xyz w, front side) interpolated. Where the
// mapped normal faces away from `geometric` (the flat normal on the ray's side), `interpolated`.
// The back of a double-sided surface takes the front's mapped normal, negated.
BP_FN float3 normal_mapped_at(const TextureSet* set, BP_GLOBAL const float* tangents, bp_u32 material, bp_u32 triangle,
                              float b1, float b2, float3 interpolated, float3 geometric, int front) {
  BP_GLOBAL const MaterialTextures* mt = &set->materials[material];
  if (mt->normal == BP_NO_TEXTURE) return interpolated;
  BP_GLOBAL const float* c = tangents + 12u * triangle;
  float b0 = 1.0f - b1 - b2;
  float3 t = bp_load3(c) * b0 + bp_load3(c + 4) * b1 + bp_load3(c + 8) * b2;
  float w = c[3] * b0 + c[7] * b1 + c[11] * b2;  // corners disagree only across a mirrored-UV seam: its sign
  float3 n = front ? interpolated : -interpolated;
  float3 n_ts = normal_map_tangent_space(texture_at(set, mt->normal, triangle, b1, b2), mt->normal_scale);
  float3 mapped = normal_map_to_world(n, t, w, n_ts);
  if (!front) mapped = -mapped;
  return dot(mapped, geometric) > 0.0f ? mapped : interpolated;  // the shading normal's trap (DESIGN.md §6)
}

#endif  // BP_SHARED_NORMAL_MAP_H

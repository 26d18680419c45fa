// glTF's normalTexture (docs/design.md §6): a tangent-space normal per texel, turned into the world by
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

// n_ts of an image read through KHR_texture_transform's uv' = A uv + t (A: transform[0..3], column-major)
// turned into the frame of the untransformed uv, which TANGENT and its handedness describe, so that a
// rotated or mirrored map's slopes turn with its image. In image axes (x, y) = (u, -v) the map is
// J = D A D, D = diag(1, -1); a height field's gradient turns by J^T (the chain rule), and as the
// tangents keep only directions, so does J here: its rotation or mirror R by the polar decomposition,
//   det J >= 0: R ~ (a + d, b - c; c - b, a + d),   det J < 0: R ~ (a - d, b + c; b + c, d - a),
// with J = (a b; c d) = (t0 -t2; -t1 t3), then (x, y) = R^T (x', y'). Exact for rotations, mirrors
// and uniform scales; a non-uniform scale keeps the map's tilt and turns it by R alone.
BP_FN float3 normal_map_untransformed(BP_GLOBAL const float* transform, float3 n_ts) {
  float a = transform[0], b = -transform[2], c = -transform[1], d = transform[3];
  int mirrored = a * d - b * c < 0.0f;
  float r00 = mirrored ? a - d : a + d, r01 = mirrored ? b + c : b - c;
  float r10 = mirrored ? b + c : c - b, r11 = mirrored ? d - a : a + d;
  float len = sqrt(r00 * r00 + r01 * r01);
  if (!(len > 0.0f)) return n_ts;  // a degenerate transform: no frame to turn to
  return make_float3((r00 * n_ts.x + r10 * n_ts.y) / len, (r01 * n_ts.x + r11 * n_ts.y) / len, n_ts.z);
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
  n_ts = normal_map_untransformed(set->views[mt->normal].transform, n_ts);
  float3 mapped = normal_map_to_world(n, t, w, n_ts);
  if (!front) mapped = -mapped;
  return dot(mapped, geometric) > 0.0f ? mapped : interpolated;  // the shading normal's trap (docs/design.md §6)
}

#endif  // BP_SHARED_NORMAL_MAP_H

// What a path vertex knows of the surface it hit: position, the normal on the side the ray came
// from, the material, and the patch (docs/design.md §6: a double-sided triangle's back is its own patch).
#ifndef BP_SHARED_SURFACE_H
#define BP_SHARED_SURFACE_H
#include "shared/compat.h"
#include "shared/normal_map.h"
#include "shared/cluster.h"
#include "shared/types.h"

typedef struct {
  float3 position;
  float3 normal;       // flat patch normal, on the side of the incoming ray: offsets, sides, weight inputs
  float3 shading_normal;  // for BSDF evaluation and sampling: NORMAL interpolated, else the flat one (docs/design.md §6)
  bp_u32 material;
  bp_u32 patch;
  int reflects;        // 0: the back of a single-sided surface (black, emits nothing)
} SurfaceHit;

BP_FN SurfaceHit surface_at(BP_GLOBAL const TriangleShading* shading, BP_GLOBAL const ClusterFan* fans,
                            bp_u32 triangle, float b1, float b2, float3 position, float3 ray_dir) {
  BP_GLOBAL const TriangleShading* t = &shading[triangle];
  BP_GLOBAL const float* nf = t->normal;
  float3 n = make_float3(nf[0], nf[1], nf[2]);
  int front = dot(n, ray_dir) < 0.0f;
  SurfaceHit s;
  s.position = position;
  s.normal = front ? n : -n;
  s.shading_normal = s.normal;
  s.material = t->material;
  PatchPlace place = patch_place(t, fans, b1, b2, position);
  bp_u32 k = place.patch_subdiv;
  s.patch = place.first_patch + (front ? 0u : k * k) + patch_local_index(place.b1, place.b2, k);
  s.reflects = front;
  return s;
}

// The shading normal at barycentrics (b1, b2) of `triangle`: its corners' NORMAL (9 floats per
// triangle, front side) interpolated and normalised, turned to the side of `geometric` (the flat
// normal on the incoming ray's side). Where it would face away from the geometric normal (bent
// corners at a crease), the flat normal.
BP_FN float3 shading_normal_at(BP_GLOBAL const float* normals, bp_u32 triangle, float b1, float b2, float3 geometric,
                               int front) {
  BP_GLOBAL const float* c = normals + 9u * triangle;
  float3 n = bp_load3(c) * (1.0f - b1 - b2) + bp_load3(c + 3) * b1 + bp_load3(c + 6) * b2;
  float len = length(n);
  if (!(len > 0.0f)) return geometric;
  n = (front ? n : -n) / len;
  return dot(n, geometric) > 0.0f ? n : geometric;
}

// surface_at with the shading normal filled in where the scene has NORMAL corners (has_normals),
// and perturbed by the material's normal map where it has one (`set` with uv_slots > 0: textures;
// `tangents`: 12 floats per triangle, normal_map.h).
BP_FN SurfaceHit surface_at_shaded(BP_GLOBAL const TriangleShading* shading, BP_GLOBAL const ClusterFan* fans,
                                   BP_GLOBAL const float* normals,
                                   bp_u32 has_normals, const TextureSet* set, BP_GLOBAL const float* tangents,
                                   bp_u32 triangle, float b1, float b2, float3 position, float3 ray_dir) {
  SurfaceHit s = surface_at(shading, fans, triangle, b1, b2, position, ray_dir);
  if (!BP_FEATURE_SHADING_NORMALS || !has_normals) return s;
  s.shading_normal = shading_normal_at(normals, triangle, b1, b2, s.normal, s.reflects);
  if (BP_FEATURE_NORMAL_MAPS && set->uv_slots > 0u)
    s.shading_normal = normal_mapped_at(set, tangents, s.material, triangle, b1, b2, s.shading_normal, s.normal, s.reflects);
  return s;
}

#endif  // BP_SHARED_SURFACE_H

// What a path vertex knows of the surface it hit: position, the normal on the side the ray came
// from, the material, and the patch (DESIGN.md §6: a double-sided triangle's back is its own patch).
#ifndef BP_SHARED_SURFACE_H
#define BP_SHARED_SURFACE_H
#include "shared/compat.h"
#include "shared/patch.h"
#include "shared/types.h"

typedef struct {
  float3 position;
  float3 normal;       // flat patch normal, on the side of the incoming ray
  bp_u32 material;
  bp_u32 patch;
  int reflects;        // 0: the back of a single-sided surface (black, emits nothing)
} SurfaceHit;

BP_FN SurfaceHit surface_at(BP_GLOBAL const TriangleShading* shading, bp_u32 triangle, float b1, float b2,
                            float3 position, float3 ray_dir) {
  BP_GLOBAL const TriangleShading* t = &shading[triangle];
  BP_GLOBAL const float* nf = t->normal;
  float3 n = make_float3(nf[0], nf[1], nf[2]);
  int front = dot(n, ray_dir) < 0.0f;
  SurfaceHit s;
  s.position = position;
  s.normal = front ? n : -n;
  s.material = t->material;
  bp_u32 k = t->patch_subdiv;
  s.patch = t->first_patch + (front ? 0u : k * k) + patch_local_index(b1, b2, k);
  s.reflects = front;
  return s;
}

#endif  // BP_SHARED_SURFACE_H

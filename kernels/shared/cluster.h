// Where a hit on a scene triangle lies among the patches (docs/design.md §6, §12): on the triangle's own
// sub-triangle grid, or, for a triangle merged into a cluster, on the grid of the cluster's fan
// triangle that holds the hit point. The path tracer (its patch-level weight inputs) and the eye
// gather (its element and Gouraud corners) read the same place, so PT and RB agree on the patch.
#ifndef BP_SHARED_CLUSTER_H
#define BP_SHARED_CLUSTER_H
#include "shared/compat.h"
#include "shared/patch.h"
#include "shared/types.h"

typedef struct {
  bp_u32 first_patch, patch_subdiv, first_element;  // of the patch triangle (TriangleShading's meaning)
  float b1, b2;                                     // the hit's barycentrics on it
} PatchPlace;

BP_FN PatchPlace patch_place(BP_GLOBAL const TriangleShading* t, BP_GLOBAL const ClusterFan* fans, float b1, float b2,
                             float3 position) {
  PatchPlace place;
  place.first_patch = t->first_patch;
  place.patch_subdiv = t->patch_subdiv;
  place.first_element = t->first_element;
  place.b1 = b1;
  place.b2 = b2;
  // the fan triangle the point is most inside of (float rounding near a fan edge: either side is right)
  float best = -INFINITY;
  for (bp_u32 i = 0u; i < t->cluster_fans; ++i) {
    BP_GLOBAL const ClusterFan* f = &fans[t->cluster_first_fan + i];
    float3 d = position - bp_load3(f->p0);
    float c1 = dot(d, bp_load3(f->dual1)), c2 = dot(d, bp_load3(f->dual2));  // barycentrics: ClusterFan
    float inside = fmin(fmin(c1, c2), 1.0f - c1 - c2);
    if (inside > best) {
      best = inside;
      place.first_patch = f->first_patch;
      place.patch_subdiv = f->patch_subdiv;
      place.first_element = f->first_element;
      place.b1 = c1;
      place.b2 = c2;
    }
  }
  return place;
}

#endif  // BP_SHARED_CLUSTER_H

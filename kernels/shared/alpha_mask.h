// alphaMode MASK (docs/design.md §6): where a material's alpha (base colour factor x texel) is below
// its cutoff there is no surface, for every ray -- camera, bounce and shadow rays -- and for RB's
// fragments alike. Rays continue past such hits.
#ifndef BP_SHARED_ALPHA_MASK_H
#define BP_SHARED_ALPHA_MASK_H
#include "shared/bvh.h"
#include "shared/compat.h"
#include "shared/texture.h"
#include "shared/types.h"

#define BP_MAX_ALPHA_SKIPS 64u  // cut-away hits one ray passes at most (then it ends there: no hit)

// The closest hit along the ray before t_max that is a surface; masks 0: the scene has none (the
// plain closest hit). Passing a cut-away hit restarts just beyond it (`step` metres on).
BP_FN int closest_surface_hit(BP_GLOBAL const BvhNode* nodes, BP_GLOBAL const BvhTriangle* tris,
                              BP_GLOBAL const TriangleShading* shading, const TextureSet* set, bp_u32 masks,
                              float3 origin, float3 dir, float t_max, float step, Hit* hit) {
  if (!BP_FEATURE_TEXTURES || !masks) return bvh_closest_hit(nodes, tris, origin, dir, t_max, hit);
  float t0 = 0.0f;
  for (bp_u32 k = 0u; k < BP_MAX_ALPHA_SKIPS; ++k) {
    if (!bvh_closest_hit(nodes, tris, origin + dir * t0, dir, t_max - t0, hit)) return 0;
    if (alpha_is_surface(set, shading[hit->triangle].material, hit->triangle, hit->b1, hit->b2)) {
      hit->t += t0;
      return 1;
    }
    t0 += hit->t + step;
    if (!(t0 < t_max)) return 0;
  }
  return 0;
}

// Whether a surface lies along the ray before t_max (a shadow ray).
BP_FN int surface_occludes(BP_GLOBAL const BvhNode* nodes, BP_GLOBAL const BvhTriangle* tris,
                           BP_GLOBAL const TriangleShading* shading, const TextureSet* set, bp_u32 masks,
                           float3 origin, float3 dir, float t_max, float step) {
  if (!BP_FEATURE_TEXTURES || !masks) return bvh_occluded(nodes, tris, origin, dir, t_max);
  Hit hit;
  return closest_surface_hit(nodes, tris, shading, set, masks, origin, dir, t_max, step, &hit);
}

#endif  // BP_SHARED_ALPHA_MASK_H

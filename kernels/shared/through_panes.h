// Rays through thin-walled transmitters (thin_glass.h, docs/design.md §11): a pane is a filter on a
// segment, not a vertex. Shadow rays pass every pane with its transmittance; PT's rays and RB's eye
// rays choose at each pane to pass, or to stop there (the mirror, the opaque rest).
#ifndef BP_SHARED_THROUGH_PANES_H
#define BP_SHARED_THROUGH_PANES_H
#include "shared/alpha_mask.h"
#include "shared/brdf.h"
#include "shared/compat.h"
#include "shared/rng.h"
#include "shared/thin_glass.h"
#include "shared/types.h"

#define BP_MAX_PANE_CROSSINGS 16u  // panes one ray passes at most; beyond, the light is taken as blocked

// What reaches origin + t_max dir from the far end through the panes between: 0 where an opaque
// surface (or more than BP_MAX_PANE_CROSSINGS panes) is in between, else the product of the panes'
// transmittances at their angles. `step` metres past each pane for the next query.
BP_FN float3 shadow_transmittance(BP_GLOBAL const BvhNode* nodes, BP_GLOBAL const BvhTriangle* tris,
                                  BP_GLOBAL const TriangleShading* shading, BP_GLOBAL const Material* materials,
                                  const TextureSet* set, bp_u32 masks, float3 origin, float3 dir, float t_max,
                                  float step) {
  const float3 blocked = make_float3(0.0f, 0.0f, 0.0f);
  if (!BP_FEATURE_TRANSMISSION)
    return surface_occludes(nodes, tris, shading, set, masks, origin, dir, t_max, step) ? blocked
                                                                                        : make_float3(1.0f, 1.0f, 1.0f);
  float3 through = make_float3(1.0f, 1.0f, 1.0f);
  float t0 = 0.0f;
  for (bp_u32 k = 0u; k <= BP_MAX_PANE_CROSSINGS; ++k) {
    Hit hit;
    if (!closest_surface_hit(nodes, tris, shading, set, masks, origin + dir * t0, dir, t_max - t0, step, &hit))
      return through;
    BP_GLOBAL const TriangleShading* t = &shading[hit.triangle];
    BP_GLOBAL const Material* m = &materials[t->material];
    if (!(m->flags & BP_MATERIAL_THIN_TRANSMITTER) || k == BP_MAX_PANE_CROSSINGS) return blocked;
    through *= pane_optics(m, dot(bp_load3(t->normal), dir)).transmittance;
    if (through.x + through.y + through.z <= 0.0f) return blocked;
    t0 += hit.t + step;
    if (!(t0 < t_max)) return through;
  }
  return blocked;
}

// The rest's reflectance on the side of `shading` that dir hits: 0 behind a single-sided surface.
BP_FN float pane_rest_albedo(BP_GLOBAL const TriangleShading* t, BP_GLOBAL const Material* m, float3 dir) {
  int front = dot(bp_load3(t->normal), dir) < 0.0f;
  if (!front && !(m->flags & BP_MATERIAL_DOUBLE_SIDED)) return 0.0f;
  return bsdf_from_material(m).continuation;  // the BSDF's continuation s (brdf.h), of either model
}

// The closest hit along the ray where it does not pass a pane: at each pane, pass with the
// probability pane_choice gives (with_mirror 0: only pass or the rest, as RB's eye rays), the
// throughput times transmittance / P(pass). Where it stops at a pane, *pane_event says whether at its
// mirror (throughput times F T / P(mirror)) or at its rest (times 1 / P(rest)); BP_PANE_PASS where
// the hit is no pane. hit->t is the distance from origin. Returns 0 where the ray leaves the scene,
// and with *throughput 0 where it is lost (more than BP_MAX_PANE_CROSSINGS panes).
BP_FN int closest_hit_through_panes(BP_GLOBAL const BvhNode* nodes, BP_GLOBAL const BvhTriangle* tris,
                                    BP_GLOBAL const TriangleShading* shading, BP_GLOBAL const Material* materials,
                                    const TextureSet* set, bp_u32 masks, float3 origin, float3 dir, float step,
                                    int with_mirror, Rng* rng, float3* throughput, bp_u32* pane_event, Hit* hit,
                                    bp_u32* rays) {
  *pane_event = BP_PANE_PASS;
  if (!BP_FEATURE_TRANSMISSION)
    return closest_surface_hit(nodes, tris, shading, set, masks, origin, dir, BP_FLOAT_MAX, step, hit);
  float t0 = 0.0f;
  for (bp_u32 k = 0u; k <= BP_MAX_PANE_CROSSINGS; ++k) {
    if (k > 0u) *rays += 1u;
    if (!closest_surface_hit(nodes, tris, shading, set, masks, origin + dir * t0, dir, BP_FLOAT_MAX, step, hit))
      return 0;
    hit->t += t0;
    BP_GLOBAL const TriangleShading* t = &shading[hit->triangle];
    BP_GLOBAL const Material* m = &materials[t->material];
    if (!(m->flags & BP_MATERIAL_THIN_TRANSMITTER)) return 1;
    if (k == BP_MAX_PANE_CROSSINGS) {
      *throughput = make_float3(0.0f, 0.0f, 0.0f);
      return 0;
    }
    PaneOptics o = pane_optics(m, dot(bp_load3(t->normal), dir));
    PaneChoice c = pane_choice(o.transmittance, with_mirror ? o.reflectance : 0.0f, pane_rest_albedo(t, m, dir));
    // u picks pass | mirror | rest over [0, 1); each event only where its probability is positive, so
    // rounding in the sum never picks an event of probability 0
    float u = rng_uniform(rng);
    if (c.rest > 0.0f && u >= c.pass + c.mirror) {
      *pane_event = BP_PANE_REST;
      *throughput *= 1.0f / c.rest;
    } else if (c.mirror > 0.0f && u >= c.pass) {
      *pane_event = BP_PANE_MIRROR;
      *throughput *= o.reflectance / c.mirror;
    } else if (c.pass > 0.0f) {
      *throughput *= o.transmittance * (1.0f / c.pass);
      t0 = hit->t + step;
      continue;
    } else {
      *pane_event = BP_PANE_REST;  // nothing leaves the pane: its (black) rest ends the path
    }
    return 1;
  }
  return 0;
}

#endif  // BP_SHARED_THROUGH_PANES_H

// Structs of the ray-bundle pass (docs/design.md §4), shared by host and device. Float arrays only.
#ifndef BP_SHARED_BUNDLE_TYPES_H
#define BP_SHARED_BUNDLE_TYPES_H
#include "shared/compat.h"
#include "shared/types.h"

#define BP_NO_PATCH 0xffffffffu
#define BP_EYE_TEXELS 4u  // float4s per pixel of RB's eye-hit texels (bundle.cl's eye_rays)

// Bins are resolved in square tiles of BP_TILE_SIDE^2 (locality: a tile's counters stay in cache).
#define BP_TILE_SIDE 16u
#define BP_TILE_LOCAL_BITS 8u
#define BP_TILE_BINS (BP_TILE_SIDE * BP_TILE_SIDE)

BP_FN bp_u32 bundle_tiles_per_side(bp_u32 bins_per_side) { return (bins_per_side + BP_TILE_SIDE - 1u) / BP_TILE_SIDE; }

// Fragment key of bin (i, j): its tile, then its place in the tile.
BP_FN bp_u32 bundle_tile_key(bp_u32 i, bp_u32 j, bp_u32 bins_per_side) {
  bp_u32 tile = (j / BP_TILE_SIDE) * bundle_tiles_per_side(bins_per_side) + i / BP_TILE_SIDE;
  return (tile << BP_TILE_LOCAL_BITS) | ((j % BP_TILE_SIDE) * BP_TILE_SIDE + i % BP_TILE_SIDE);
}

// An element: one sub-triangle of the patch grid (kernels/shared/patch.h), i.e. one physical piece of
// surface. Its front side is patch front_patch; its back side is back_patch for double-sided
// materials, else BP_NO_PATCH (the back is black and only occludes).
typedef struct {
  float v0[3];
  bp_u32 front_patch;
  float e1[3];          // v1 - v0
  bp_u32 back_patch;
  float e2[3];          // v2 - v0
  float area;           // m^2
  float normal[3];      // unit normal of the front side
  bp_u32 material;
} BundleElement;

// Everything that changes per iteration: the direction, the random bin grid, and the previous
// direction whose incoming radiance is reflected now.
typedef struct {
  float omega[3];         // this iteration's direction (used as +omega and -omega)
  float bin_size;         // metres
  float axis_u[3];        // bin-plane axes, perpendicular to omega, randomly rotated about it
  float offset_u;         // random sub-bin offset in [0, 1)
  float axis_v[3];
  float offset_v;
  float centre[3];        // centre of the scene's bounding sphere
  bp_u32 bins_per_side;   // R + 1 (the offset grid needs one more bin than R to cover the sphere)
  float omega_prev[3];    // previous iteration's direction (its incoming radiance is reflected now)
  bp_u32 light_count;     // lights to sample (kernels/shared/lights.h); 0: no light sampling
  bp_u32 weight_mode;     // BP_WEIGHTS_*: how chain 0 is weighted (docs/design.md §3)
  bp_u32 chains;          // radiance values per patch and fragment (see below)
  float weight_ratio;     // N2 / N1
  bp_u32 eye_outputs;     // per pixel: 1 (weighted), or 2 (weighted, raw)
  float omega_next[3];    // next iteration's direction: where the light arriving now will be sent
  bp_u32 direct_chain;    // the chain of light straight from emitters (light sampling), 0: none
  bp_u32 beta_heuristic;  // BP_BETA_*: the per-vertex beta of product weights (kernels/shared/weights.h)
  float light_rate;       // probability that a patch traces its light sample in an iteration (in (0, 1])
  bp_u32 eye_direct_chain;  // the chain of direct light weighted for the eye vertex (--eye-direct shared), 0: none
  bp_u32 shading_normals;   // 1: the eye gather reflects with the eye hits' shading normals (rb_eye_hits)
  bp_u32 environment_width;   // the environment map arriving where no fragment is in front (--environment,
  bp_u32 environment_height;  //   kernels/shared/environment_map.h); 0 x 0: none
  bp_u32 environment_light;   // its index among the lights to sample; BP_NO_LIGHT: not sampled (p_L = 0)
  float contact_depth;      // metres: consecutive fragments of a bin closer than this along omega touch (no transfer)
  bp_u32 sun_own_samples;   // --rb-sun own: 1, a patch that takes its light sample also takes one of each
                            // directional light (delta_light_weights); 0: the sun only when chosen
  bp_u32 pad[3];
} BundleIteration;

// Chains per patch and fragment: chain 0 is the weighted one. With light sampling (product weights)
// chain direct_chain = 1 holds the light that arrives straight from emitters, weighted per fragment
// as the RB bundle technique of the last segment (docs/design.md §3), and chain 0 then holds the rest.
// With --eye-direct shared, chain eye_direct_chain = 2 holds the same light weighted for the eye
// vertex (eye_segment_weights), which the eye estimate adds; the patches' light samples for the eye
// go to a buffer of their own (their direction differs per patch).
// The unweighted chain of --weights product (the rb_raw layer), when kept, is the last one. In the
// paper's mode chain 0 is unweighted and its .w carries ln of the paper's P (eq. 10) of the radiance.

// One cached primary hit per pixel: the patch the eye sees and where on it.
typedef struct {
  bp_u32 patch;           // BP_NO_PATCH: the ray left the scene or hit a black back side
  bp_u32 element;         // with patch BP_NO_PATCH: BP_NO_PATCH where the ray left the scene (sees the environment)
  float l1, l2;           // barycentrics within the element (weights of its corners 1 and 2)
  float wo[3];            // towards the eye
  float pad0;
  float filter[3];        // the thin panes the eye ray passed (through_panes.h): their transmittance / P(pass),
  float pad1;             //   and 1 / P(rest) where it stopped at a pane's opaque rest; 1 without panes
} EyeHit;

#endif  // BP_SHARED_BUNDLE_TYPES_H

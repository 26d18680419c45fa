// Global ray-bundle iteration (DESIGN.md §4) with a software transillumination buffer. One iteration:
//   rb_outgoing -> rb_count -> scan -> rb_emit -> rb_tile_count -> scan -> rb_tile_scatter
//   -> rb_tile_resolve -> rb_gather -> (rb_vertex -> rb_eye)
// Patch radiance is kept as E_in = L_in cos(theta_in) ("irradiance over pi"), so an element seen
// edge-on never divides by its cosine.
#include "shared/types.h"
#include "shared/bundle_types.h"
#include "shared/bundle_raster.h"
#include "shared/brdf.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/rng.h"
#include "shared/surface.h"
#include "scan.cl"

#define BP_BACK_SIDE 0x80000000u

// Normal of a patch (its element's normal, flipped for a back side).
static float3 patch_normal(__global const BundleElement* elements, uint patch_element) {
  __global const BundleElement* e = &elements[patch_element & ~BP_BACK_SIDE];
  float3 n = bp_load3(e->normal);
  return (patch_element & BP_BACK_SIDE) ? -n : n;
}

// The direction along +-omega that leaves a patch's side: omega or -omega, whichever is in front.
static float3 facing(float3 n, float3 omega) { return dot(n, omega) >= 0.0f ? omega : -omega; }

// 1. Outgoing radiance of every patch along the new direction: the random operator T* applied to the
//    previous incoming radiance, L_out = Le + 2 pi f(w_prev -> w_out) cos(theta_prev) L_in.
__kernel void rb_outgoing(__global const BundleElement* elements, __global const uint* patch_element,
                          __global const Material* materials, __global const float4* e_in,
                          const BundleIteration it, const uint patches, __global float4* l_out) {
  uint p = (uint)get_global_id(0);
  if (p >= patches) return;
  uint pe = patch_element[p];
  float3 n = patch_normal(elements, pe);
  Bsdf bsdf = bsdf_from_material(&materials[elements[pe & ~BP_BACK_SIDE].material]);
  float3 wi = facing(n, bp_private3(it.omega_prev));
  float3 wo = facing(n, bp_private3(it.omega));
  float4 e = e_in[p];
  float3 reflected = bsdf_eval(&bsdf, n, wi, wo) * make_float3(e.x, e.y, e.z) * BP_TWO_PI;
  float3 l = bsdf.emission + reflected;
  l_out[p] = (float4)(l.x, l.y, l.z, 0.0f);
}

// 2. Bins covered by each element.
__kernel void rb_count(__global const BundleElement* elements, const BundleIteration it, const uint count,
                       __global uint* fragment_counts) {
  uint e = (uint)get_global_id(0);
  if (e >= count) return;
  RasterElement r = raster_setup(&elements[e], &it);
  fragment_counts[e] = raster_count(&r);
}

// 3. Fragments (tile key, depth, element), emitted grouped by element at the scanned offsets. The
//    key packs the bin as its 16x16 tile and its place in the tile: tile << 8 | local bin.
__kernel void rb_emit(__global const BundleElement* elements, const BundleIteration it, const uint count,
                      __global const uint* fragment_offsets, __global uint* fragment_key,
                      __global float* fragment_depth, __global uint* fragment_element) {
  uint e = (uint)get_global_id(0);
  if (e >= count) return;
  RasterElement r = raster_setup(&elements[e], &it);
  uint slot = fragment_offsets[e];
  for (int j = r.j0; j <= r.j1; ++j) {
    int first, last;
    raster_row_span(&r, j, &first, &last);
    for (int i = first; i <= last; ++i) {
      fragment_key[slot] = bundle_tile_key((uint)i, (uint)j, it.bins_per_side);
      fragment_depth[slot] = raster_depth(&r, i, j);
      fragment_element[slot] = e;
      ++slot;
    }
  }
}

// 4. Counting sort by tile: count, (scan), scatter. The scatter also copies each fragment's depth,
//    element and local bin next to its tile's other fragments, so a tile is resolved from one
//    contiguous range.
__kernel void rb_tile_count(__global const uint* fragment_key, const uint fragments, __global uint* tile_counts) {
  uint f = (uint)get_global_id(0);
  if (f >= fragments) return;
  atomic_inc(&tile_counts[fragment_key[f] >> BP_TILE_LOCAL_BITS]);
}

__kernel void rb_tile_scatter(__global const uint* fragment_key, __global const float* fragment_depth,
                              __global const uint* fragment_element, const uint fragments,
                              __global uint* tile_cursor, __global uint* tiled_slot, __global uint* tiled_local,
                              __global float* tiled_depth, __global uint* tiled_element) {
  uint f = (uint)get_global_id(0);
  if (f >= fragments) return;
  uint key = fragment_key[f];
  uint at = atomic_inc(&tile_cursor[key >> BP_TILE_LOCAL_BITS]);
  tiled_slot[at] = f;
  tiled_local[at] = key & (BP_TILE_BINS - 1u);
  tiled_depth[at] = fragment_depth[f];
  tiled_element[at] = fragment_element[f];
}

// Depth order within a bin; ties (touching elements) broken by element index so the order, and
// so the image, does not depend on the scatter's race.
static int fragment_before(__global const float* depth, __global const uint* element, uint a, uint b) {
  float da = depth[a], db = depth[b];
  return da < db || (da == db && element[a] < element[b]);
}

// The sides of an element as seen along omega: the patch facing -omega (towards smaller depth) and
// the one facing +omega; BP_NO_PATCH for the black back of a single-sided surface.
static void sides_along(__global const BundleElement* e, float3 omega, uint* minus_patch, uint* plus_patch) {
  int front_faces_minus = dot(bp_load3(e->normal), omega) < 0.0f;
  *minus_patch = front_faces_minus ? e->front_patch : e->back_patch;
  *plus_patch = front_faces_minus ? e->back_patch : e->front_patch;
}

// 5. Resolve one tile: counting sort of its fragments by bin (private counters), depth sort per bin,
//    then the transfer: consecutive fragments exchange radiance. The side of a fragment facing
//    -omega receives what the previous fragment sends along +omega, the other side what the next
//    one sends along -omega; nothing in front: the (black) background.
__kernel void rb_tile_resolve(__global const BundleElement* elements, __global const uint* tile_start,
                              __global const uint* tiled_slot, __global const uint* tiled_local,
                              __global const float* tiled_depth, __global const uint* tiled_element,
                              __global uint* tile_order, __global const float4* l_out, const BundleIteration it,
                              const uint tiles, __global float4* received_minus, __global float4* received_plus) {
  uint tile = (uint)get_global_id(0);
  if (tile >= tiles) return;
  uint begin = tile_start[tile], end = tile_start[tile + 1];
  if (begin == end) return;
  uint bin_start[BP_TILE_BINS + 1];
  for (uint b = 0; b <= BP_TILE_BINS; ++b) bin_start[b] = 0u;
  for (uint a = begin; a < end; ++a) bin_start[tiled_local[a] + 1u] += 1u;
  for (uint b = 0; b < BP_TILE_BINS; ++b) bin_start[b + 1] += bin_start[b];
  uint cursor[BP_TILE_BINS];
  for (uint b = 0; b < BP_TILE_BINS; ++b) cursor[b] = bin_start[b];
  for (uint a = begin; a < end; ++a) tile_order[begin + cursor[tiled_local[a]]++] = a;

  const float3 omega = bp_private3(it.omega);
  const float4 zero = (float4)(0.0f, 0.0f, 0.0f, 0.0f);
  for (uint b = 0; b < BP_TILE_BINS; ++b) {
    uint first = begin + bin_start[b], last = begin + bin_start[b + 1];
    if (first == last) continue;
    for (uint a = first + 1; a < last; ++a) {  // insertion sort: lists are the scene's depth complexity
      uint x = tile_order[a], c = a;
      while (c > first && fragment_before(tiled_depth, tiled_element, x, tile_order[c - 1])) {
        tile_order[c] = tile_order[c - 1];
        --c;
      }
      tile_order[c] = x;
    }
    float4 from_previous = zero;  // what arrives along +omega at the current fragment
    uint minus_patch, plus_patch;
    sides_along(&elements[tiled_element[tile_order[first]]], omega, &minus_patch, &plus_patch);
    for (uint a = first; a < last; ++a) {
      uint slot = tiled_slot[tile_order[a]];
      received_minus[slot] = from_previous;
      from_previous = plus_patch != BP_NO_PATCH ? l_out[plus_patch] : zero;
      if (a + 1 < last) {
        sides_along(&elements[tiled_element[tile_order[a + 1]]], omega, &minus_patch, &plus_patch);
        received_plus[slot] = minus_patch != BP_NO_PATCH ? l_out[minus_patch] : zero;
      } else {
        received_plus[slot] = zero;
      }
    }
  }
}

// 6. New incoming radiance per patch: transferred power over area. With n_bins covered,
//    E[n_bins] = A |cos theta| / A_bin, so E_in = sum L_out * A_bin / A estimates L_in cos theta.
__kernel void rb_gather(__global const BundleElement* elements, __global const uint* fragment_offsets,
                        __global const uint* fragment_counts, __global const float4* received_minus,
                        __global const float4* received_plus, const BundleIteration it, const uint count,
                        __global float4* e_in) {
  uint e = (uint)get_global_id(0);
  if (e >= count) return;
  __global const BundleElement* el = &elements[e];
  uint begin = fragment_offsets[e], end = begin + fragment_counts[e];
  float4 sum_minus = (float4)(0.0f), sum_plus = (float4)(0.0f);
  for (uint s = begin; s < end; ++s) {
    sum_minus += received_minus[s];
    sum_plus += received_plus[s];
  }
  float scale = it.bin_size * it.bin_size / el->area;
  uint minus_patch, plus_patch;
  sides_along(el, bp_private3(it.omega), &minus_patch, &plus_patch);
  if (minus_patch != BP_NO_PATCH) e_in[minus_patch] = sum_minus * scale;
  if (plus_patch != BP_NO_PATCH) e_in[plus_patch] = sum_plus * scale;
}

// Primary hits for the eye estimate, jittered within the pixel like the path tracer's.
__kernel void rb_eye_hits(__global const BvhNode* nodes, __global const BvhTriangle* triangles,
                          __global const TriangleShading* shading, __global const Material* materials,
                          const CameraParams camera, const uint seed, const uint jitter_index,
                          __global EyeHit* hits) {
  uint pixel = (uint)get_global_id(0);
  if (pixel >= camera.width * camera.height) return;
  Rng rng = rng_init(seed, pixel, jitter_index);
  float jx = rng_uniform(&rng), jy = rng_uniform(&rng);
  float3 origin = make_float3(camera.position[0], camera.position[1], camera.position[2]);
  float3 dir = camera_ray_direction(&camera, pixel % camera.width, pixel / camera.width, jx, jy);
  EyeHit out;
  out.patch = BP_NO_PATCH;
  out.element = 0u;
  out.l1 = out.l2 = 0.0f;
  out.wo[0] = -dir.x; out.wo[1] = -dir.y; out.wo[2] = -dir.z;
  out.pad0 = 0.0f;
  Hit hit;
  if (bvh_closest_hit(nodes, triangles, origin, dir, BP_FLOAT_MAX, &hit)) {
    SurfaceHit s = surface_at(shading, hit.triangle, hit.b1, hit.b2, origin + dir * hit.t, dir);
    if (s.reflects || (materials[s.material].flags & BP_MATERIAL_DOUBLE_SIDED)) {
      __global const TriangleShading* t = &shading[hit.triangle];
      out.patch = s.patch;
      out.element = t->first_element + patch_local_index(hit.b1, hit.b2, t->patch_subdiv);
      patch_local_barycentrics(hit.b1, hit.b2, t->patch_subdiv, &out.l1, &out.l2);
    }
  }
  hits[pixel] = out;
}

// Gouraud vertices: the area-weighted mean E_in of the patches around each welded corner.
__kernel void rb_vertex(__global const uint* vertex_patch_start, __global const uint* vertex_patches,
                        __global const BundleElement* elements, __global const uint* patch_element,
                        __global const float4* e_in, const uint vertices, __global float4* e_vertex) {
  uint v = (uint)get_global_id(0);
  if (v >= vertices) return;
  float4 sum = (float4)(0.0f);
  float area = 0.0f;
  for (uint k = vertex_patch_start[v]; k < vertex_patch_start[v + 1]; ++k) {
    uint p = vertex_patches[k];
    float a = elements[patch_element[p] & ~BP_BACK_SIDE].area;
    sum += e_in[p] * a;
    area += a;
  }
  e_vertex[v] = area > 0.0f ? sum / area : (float4)(0.0f);
}

// 7. Eye estimate of this iteration: the primary hit reflects its patch's incoming radiance towards
//    the eye, Le + 2 pi f(w_in -> w_view) cos(theta_in) L_in, added to the pixel's running sum.
//    E_in is the patch's own (flat) or interpolated from its corners' vertices (Gouraud).
__kernel void rb_eye(__global const EyeHit* hits, __global const BundleElement* elements,
                     __global const uint* patch_element, __global const Material* materials,
                     __global const float4* e_in, __global const uint* patch_vertices,
                     __global const float4* e_vertex, const uint gouraud, const BundleIteration it,
                     const uint pixels, __global float4* pixel_sum) {
  uint pixel = (uint)get_global_id(0);
  if (pixel >= pixels) return;
  EyeHit h = hits[pixel];
  if (h.patch == BP_NO_PATCH) return;
  uint pe = patch_element[h.patch];
  float3 n = patch_normal(elements, pe);
  Bsdf bsdf = bsdf_from_material(&materials[elements[pe & ~BP_BACK_SIDE].material]);
  float3 wo = make_float3(h.wo[0], h.wo[1], h.wo[2]);
  float3 wi = facing(n, bp_private3(it.omega));
  float4 e;
  if (gouraud) {
    __global const uint* pv = &patch_vertices[3 * h.patch];
    e = e_vertex[pv[0]] * (1.0f - h.l1 - h.l2) + e_vertex[pv[1]] * h.l1 + e_vertex[pv[2]] * h.l2;
  } else {
    e = e_in[h.patch];
  }
  float3 l = bsdf.emission + bsdf_eval(&bsdf, n, wi, wo) * make_float3(e.x, e.y, e.z) * BP_TWO_PI;
  pixel_sum[pixel] += (float4)(l.x, l.y, l.z, 0.0f);
}

// Global ray-bundle iteration (DESIGN.md §4) with a software transillumination buffer. One iteration:
//   rb_outgoing -> rb_count -> scan -> rb_emit -> rb_bin_count -> scan -> rb_bin_scatter
//   -> rb_transfer -> rb_gather -> (rb_eye)
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
  uint covered = 0u;
  float depth;
  for (int j = r.j0; j <= r.j1; ++j)
    for (int i = r.i0; i <= r.i1; ++i) covered += (uint)raster_covers(&r, i, j, &depth);
  fragment_counts[e] = covered;
}

// 3. Fragments (bin, depth, element), emitted grouped by element at the scanned offsets.
__kernel void rb_emit(__global const BundleElement* elements, const BundleIteration it, const uint count,
                      __global const uint* fragment_offsets, __global uint* fragment_bin,
                      __global float* fragment_depth, __global uint* fragment_element) {
  uint e = (uint)get_global_id(0);
  if (e >= count) return;
  RasterElement r = raster_setup(&elements[e], &it);
  uint slot = fragment_offsets[e];
  float depth;
  for (int j = r.j0; j <= r.j1; ++j)
    for (int i = r.i0; i <= r.i1; ++i)
      if (raster_covers(&r, i, j, &depth)) {
        fragment_bin[slot] = (uint)j * it.bins_per_side + (uint)i;
        fragment_depth[slot] = depth;
        fragment_element[slot] = e;
        ++slot;
      }
}

// 4. Counting sort by bin: count, (scan), scatter.
__kernel void rb_bin_count(__global const uint* fragment_bin, const uint fragments, __global uint* bin_counts) {
  uint f = (uint)get_global_id(0);
  if (f >= fragments) return;
  atomic_inc(&bin_counts[fragment_bin[f]]);
}

__kernel void rb_bin_scatter(__global const uint* fragment_bin, const uint fragments,
                             __global uint* bin_cursor, __global uint* sorted_slots) {
  uint f = (uint)get_global_id(0);
  if (f >= fragments) return;
  sorted_slots[atomic_inc(&bin_cursor[fragment_bin[f]])] = f;
}

// Depth order within a bin; ties (touching elements) broken by element index so the order, and
// so the image, does not depend on the scatter's race.
static int fragment_before(__global const float* depth, __global const uint* element, uint a, uint b) {
  float da = depth[a], db = depth[b];
  return da < db || (da == db && element[a] < element[b]);
}

// 5. Transfer: consecutive fragments exchange radiance. The side of a fragment that faces -omega
//    (towards smaller depth) receives what the previous fragment sends along +omega, and the other
//    side receives what the next one sends along -omega; nothing in front: the (black) background.
__kernel void rb_transfer(__global const BundleElement* elements, __global const float* fragment_depth,
                          __global const uint* fragment_element, __global const uint* bin_start,
                          __global uint* sorted_slots, __global const float4* l_out, const BundleIteration it,
                          const uint bins, __global float4* received_minus, __global float4* received_plus) {
  uint bin = (uint)get_global_id(0);
  if (bin >= bins) return;
  uint begin = bin_start[bin], end = bin_start[bin + 1];
  if (begin == end) return;
  // Insertion sort in place: lists are short (the depth complexity of the scene).
  for (uint a = begin + 1; a < end; ++a) {
    uint slot = sorted_slots[a], b = a;
    while (b > begin && fragment_before(fragment_depth, fragment_element, slot, sorted_slots[b - 1])) {
      sorted_slots[b] = sorted_slots[b - 1];
      --b;
    }
    sorted_slots[b] = slot;
  }
  float3 omega = bp_private3(it.omega);
  float4 zero = (float4)(0.0f, 0.0f, 0.0f, 0.0f);
  float4 from_previous = zero;  // what arrives along +omega at the current fragment
  for (uint a = begin; a < end; ++a) {
    uint slot = sorted_slots[a];
    __global const BundleElement* e = &elements[fragment_element[slot]];
    int front_faces_minus = dot(bp_load3(e->normal), omega) < 0.0f;
    uint minus_patch = front_faces_minus ? e->front_patch : e->back_patch;
    uint plus_patch = front_faces_minus ? e->back_patch : e->front_patch;
    received_minus[slot] = from_previous;
    from_previous = plus_patch != BP_NO_PATCH ? l_out[plus_patch] : zero;
    if (a + 1 < end) {
      __global const BundleElement* next = &elements[fragment_element[sorted_slots[a + 1]]];
      int next_front_faces_minus = dot(bp_load3(next->normal), omega) < 0.0f;
      uint next_minus = next_front_faces_minus ? next->front_patch : next->back_patch;
      received_plus[slot] = next_minus != BP_NO_PATCH ? l_out[next_minus] : zero;
    } else {
      received_plus[slot] = zero;
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
  int front_faces_minus = dot(bp_load3(el->normal), bp_private3(it.omega)) < 0.0f;
  uint minus_patch = front_faces_minus ? el->front_patch : el->back_patch;
  uint plus_patch = front_faces_minus ? el->back_patch : el->front_patch;
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

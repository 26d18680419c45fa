// Rasterizing an element into the bins of the transillumination buffer (docs/design.md §4): an element
// covers a bin when the bin's centre lies inside its projection, found row by row as a span. The bin grid has a random
// sub-bin offset every iteration, so the expected number of covered bins is exactly the projected
// area over the bin area — what makes the gather unbiased, also for elements smaller than a bin.
#ifndef BP_SHARED_BUNDLE_RASTER_H
#define BP_SHARED_BUNDLE_RASTER_H
#include "shared/bundle_types.h"
#include "shared/compat.h"

typedef struct {
  float x[3], y[3];       // corners in bin units: bin (i, j) has its centre at (i + 0.5, j + 0.5)
  float depth[3];         // dot(corner, omega)
  float inv_double_area;  // 1 / (twice the signed projected area), in bin units
  float orientation;      // +1 or -1: makes every edge function non-negative inside
  bp_i32 i0, i1, j0, j1;  // inclusive bin range to test (empty when i1 < i0)
  // Edge k (from corner k+1 to corner k+2) at height py, scaled so inside is >= 0: slope x + rise py + base.
  // Where slope != 0 it crosses the row at x = cross_py py + cross_0 (set up once, not per row).
  float slope[3], rise[3], base[3], cross_py[3], cross_0[3];
  float depth_dx, depth_dy, depth_0;  // the plane's depth at bin centre (px, py): depth_0 + depth_dx px + depth_dy py
} RasterElement;

BP_FN float raster_edge(float ax, float ay, float bx, float by, float px, float py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

BP_FN RasterElement raster_setup(BP_GLOBAL const BundleElement* e, const BundleIteration* it) {
  RasterElement r;
  float3 v0 = bp_load3(e->v0), e1 = bp_load3(e->e1), e2 = bp_load3(e->e2);
  float3 c = bp_private3(it->centre), u = bp_private3(it->axis_u), v = bp_private3(it->axis_v);
  float3 w = bp_private3(it->omega);
  float inv_h = 1.0f / it->bin_size;
  float half_bins = 0.5f * (float)(it->bins_per_side - 1u);  // R / 2
  // The corners one by one, not as a private array: PoCL kept such an array in memory per work-item
  // and stalled on reloading it (a third of the emit kernel's time).
  float3 d0 = v0 - c, d1 = d0 + e1, d2 = d0 + e2;
  float x_offset = half_bins + it->offset_u, y_offset = half_bins + it->offset_v;
  r.x[0] = dot(d0, u) * inv_h + x_offset; r.y[0] = dot(d0, v) * inv_h + y_offset;
  r.x[1] = dot(d1, u) * inv_h + x_offset; r.y[1] = dot(d1, v) * inv_h + y_offset;
  r.x[2] = dot(d2, u) * inv_h + x_offset; r.y[2] = dot(d2, v) * inv_h + y_offset;
  r.depth[0] = dot(v0, w); r.depth[1] = dot(v0 + e1, w); r.depth[2] = dot(v0 + e2, w);
  float xmin = fmin(r.x[0], fmin(r.x[1], r.x[2])), xmax = fmax(r.x[0], fmax(r.x[1], r.x[2]));
  float ymin = fmin(r.y[0], fmin(r.y[1], r.y[2])), ymax = fmax(r.y[0], fmax(r.y[1], r.y[2]));
  float double_area = raster_edge(r.x[0], r.y[0], r.x[1], r.y[1], r.x[2], r.y[2]);
  r.orientation = double_area >= 0.0f ? 1.0f : -1.0f;
  r.inv_double_area = double_area != 0.0f ? 1.0f / double_area : 0.0f;
  // Bins whose centres (i + 0.5) can lie in [xmin, xmax], clipped to the grid.
  bp_i32 last = (bp_i32)it->bins_per_side - 1;
  r.i0 = (bp_i32)ceil(xmin - 0.5f); r.i1 = (bp_i32)floor(xmax - 0.5f);
  r.j0 = (bp_i32)ceil(ymin - 0.5f); r.j1 = (bp_i32)floor(ymax - 0.5f);
  r.i0 = r.i0 < 0 ? 0 : r.i0; r.j0 = r.j0 < 0 ? 0 : r.j0;
  r.i1 = r.i1 > last ? last : r.i1; r.j1 = r.j1 > last ? last : r.j1;
  if (double_area == 0.0f) r.i1 = r.i0 - 1;  // edge-on: covers no bin centre
  for (int k = 0; k < 3; ++k) {
    int a = k == 0 ? 1 : (k == 1 ? 2 : 0), b = k == 0 ? 2 : (k == 1 ? 0 : 1);
    // raster_edge(a -> b) at (px, py) = (xb - xa)(py - ya) - (yb - ya)(px - xa)
    r.slope[k] = -(r.y[b] - r.y[a]) * r.orientation;
    r.rise[k] = (r.x[b] - r.x[a]) * r.orientation;
    r.base[k] = ((r.y[b] - r.y[a]) * r.x[a] - (r.x[b] - r.x[a]) * r.y[a]) * r.orientation;
    float inv_slope = r.slope[k] != 0.0f ? 1.0f / r.slope[k] : 0.0f;
    r.cross_py[k] = -r.rise[k] * inv_slope;
    r.cross_0[k] = -r.base[k] * inv_slope;
  }
  // depth = (w0 d0 + w1 d1 + w2 d2) / double_area with the edge functions w_k linear in (px, py)
  r.depth_dx = r.depth_dy = r.depth_0 = 0.0f;
  for (int k = 0; k < 3; ++k) {
    float d = r.depth[k] * r.inv_double_area * r.orientation;
    r.depth_dx += r.slope[k] * d;
    r.depth_dy += r.rise[k] * d;
    r.depth_0 += r.base[k] * d;
  }
  return r;
}

// Bins of row j whose centres lie inside the element: [*first, *last] (empty when last < first).
// Each edge function is linear in x along the row, so the row's span is the intersection of three
// half-lines, where each edge crosses the row (set up once per element). rb_emit and raster_count
// (what the tests check against brute force) walk the same spans. A centre exactly on an edge
// (probability zero under the random offset) may belong to both neighbours or neither.
BP_FN void raster_row_span(const RasterElement* r, bp_i32 j, bp_i32* first, bp_i32* last) {
  float py = (float)j + 0.5f;
  float lo = (float)r->i0 + 0.5f, hi = (float)r->i1 + 0.5f;
  for (int k = 0; k < 3; ++k) {
    float x = r->cross_py[k] * py + r->cross_0[k];
    if (r->slope[k] > 0.0f) lo = fmax(lo, x);
    else if (r->slope[k] < 0.0f) hi = fmin(hi, x);
    else if (r->rise[k] * py + r->base[k] < 0.0f) hi = lo - 1.0f;  // parallel to the row and outside
  }
  *first = (bp_i32)ceil(lo - 0.5f);
  *last = (bp_i32)floor(hi - 0.5f);
}

// Depth of the element's plane at bin (i, j)'s centre.
BP_FN float raster_depth(const RasterElement* r, bp_i32 i, bp_i32 j) {
  return r->depth_0 + r->depth_dx * ((float)i + 0.5f) + r->depth_dy * ((float)j + 0.5f);
}

// Number of bins the element covers (the tests' view of the spans rb_emit walks).
BP_FN bp_u32 raster_count(const RasterElement* r) {
  bp_u32 covered = 0u;
  for (bp_i32 j = r->j0; j <= r->j1; ++j) {
    bp_i32 first, last;
    raster_row_span(r, j, &first, &last);
    if (last >= first) covered += (bp_u32)(last - first + 1);
  }
  return covered;
}

// Most bins an element of `area` (m^2) and `perimeter` (m) can cover, for any direction and any grid
// offset, so that it can rasterize into slots of its own without counting first: a closed convex set
// of area A and perimeter P holds fewer than A + P/2 + 1 lattice points (Bokowski, Hadwiger and
// Wills, 1972), here in bin units; a projection only shrinks A and P. The margin covers centres that
// float edge functions let in within rounding of an edge (an inflated triangle: a few 1e-4 bins at
// 4096 bins). Host only, for the slot layout (and its test).
BP_FN bp_u32 raster_fragment_bound(float area, float perimeter, float bin_size) {
  float a = area / (bin_size * bin_size), p = perimeter / bin_size;
  return (bp_u32)ceil(a * 1.0001f + p * 0.501f + 3.0f);
}

#endif  // BP_SHARED_BUNDLE_RASTER_H

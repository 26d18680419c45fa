// Rasterizing an element into the bins of the transillumination buffer (DESIGN.md §4): an element
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
  float3 corner[3];
  corner[0] = v0; corner[1] = v0 + e1; corner[2] = v0 + e2;
  float xmin = BP_FLOAT_MAX, xmax = -BP_FLOAT_MAX, ymin = BP_FLOAT_MAX, ymax = -BP_FLOAT_MAX;
  for (int k = 0; k < 3; ++k) {
    float3 d = corner[k] - c;
    r.x[k] = dot(d, u) * inv_h + half_bins + it->offset_u;
    r.y[k] = dot(d, v) * inv_h + half_bins + it->offset_v;
    r.depth[k] = dot(corner[k], w);
    xmin = fmin(xmin, r.x[k]); xmax = fmax(xmax, r.x[k]);
    ymin = fmin(ymin, r.y[k]); ymax = fmax(ymax, r.y[k]);
  }
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
  return r;
}

// Bins of row j whose centres lie inside the element: [*first, *last] (empty when last < first).
// Each edge function is linear in x along the row, so the row's span is the intersection of three
// half-lines; count and emit call this same code, so they always agree. A centre exactly on an edge
// (probability zero under the random offset) may belong to both neighbours or neither.
BP_FN void raster_row_span(const RasterElement* r, bp_i32 j, bp_i32* first, bp_i32* last) {
  float py = (float)j + 0.5f;
  float lo = (float)r->i0 + 0.5f, hi = (float)r->i1 + 0.5f;
  for (int k = 0; k < 3; ++k) {
    int a = k == 0 ? 1 : (k == 1 ? 2 : 0), b = k == 0 ? 2 : (k == 1 ? 0 : 1);
    // edge(a -> b) at (x, py) = slope * x + offset, scaled by the orientation so inside is >= 0
    float slope = -(r->y[b] - r->y[a]) * r->orientation;
    float offset = ((r->x[b] - r->x[a]) * (py - r->y[a]) + (r->y[b] - r->y[a]) * r->x[a]) * r->orientation;
    if (slope > 0.0f) lo = fmax(lo, -offset / slope);
    else if (slope < 0.0f) hi = fmin(hi, -offset / slope);
    else if (offset < 0.0f) hi = lo - 1.0f;  // parallel to the row and outside
  }
  *first = (bp_i32)ceil(lo - 0.5f);
  *last = (bp_i32)floor(hi - 0.5f);
}

// Depth of the element's plane at bin (i, j)'s centre.
BP_FN float raster_depth(const RasterElement* r, bp_i32 i, bp_i32 j) {
  float px = (float)i + 0.5f, py = (float)j + 0.5f;
  float w0 = raster_edge(r->x[1], r->y[1], r->x[2], r->y[2], px, py);
  float w1 = raster_edge(r->x[2], r->y[2], r->x[0], r->y[0], px, py);
  float w2 = raster_edge(r->x[0], r->y[0], r->x[1], r->y[1], px, py);
  return (w0 * r->depth[0] + w1 * r->depth[1] + w2 * r->depth[2]) * r->inv_double_area;
}

// Number of bins the element covers.
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

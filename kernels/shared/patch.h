// Patches: a triangle is split into k^2 congruent sub-triangles (k = patch_subdiv) on a
// barycentric grid. Row r (along b2) holds 2(k-r)-1 sub-triangles and starts at r(2k-r).
// The path tracer needs only the index of the patch it hit; RB needs the corners too.
#ifndef BP_SHARED_PATCH_H
#define BP_SHARED_PATCH_H
#include "shared/compat.h"

// Local index in [0, k^2) of the sub-triangle containing barycentrics (b1, b2).
BP_FN bp_u32 patch_local_index(float b1, float b2, bp_u32 k) {
  float u = b1 * (float)k, v = b2 * (float)k;
  bp_i32 row = (bp_i32)floor(v);
  row = row < 0 ? 0 : (row > (bp_i32)k - 1 ? (bp_i32)k - 1 : row);
  bp_i32 last_col = (bp_i32)k - 1 - row;
  bp_i32 col = (bp_i32)floor(u);
  col = col < 0 ? 0 : (col > last_col ? last_col : col);
  float fu = u - (float)col, fv = v - (float)row;
  bp_u32 upper = (fu + fv > 1.0f && col < last_col) ? 1u : 0u;
  return (bp_u32)row * (2u * k - (bp_u32)row) + 2u * (bp_u32)col + upper;
}

// Barycentrics (l1, l2) within the sub-triangle that contains (b1, b2) on the parent triangle,
// relative to the corners that patch_corner_barycentrics gives.
BP_FN void patch_local_barycentrics(float b1, float b2, bp_u32 k, float* l1, float* l2) {
  bp_u32 local_index = patch_local_index(b1, b2, k);
  bp_u32 row = 0u;
  while ((row + 1u) * (2u * k - row - 1u) <= local_index) ++row;
  bp_u32 in_row = local_index - row * (2u * k - row);
  float c = (float)(in_row / 2u), r = (float)row;
  float u = b1 * (float)k, v = b2 * (float)k;
  if (in_row % 2u == 0u) {        // corners (c, r), (c+1, r), (c, r+1)
    *l1 = u - c;
    *l2 = v - r;
  } else {                        // corners (c+1, r), (c+1, r+1), (c, r+1)
    *l2 = c + 1.0f - u;
    *l1 = v - r - *l2;
  }
}

// Barycentrics (b1, b2) of the three corners of sub-triangle `local_index` (inverse of the above),
// counter-clockwise like the parent triangle.
BP_FN void patch_corner_barycentrics(bp_u32 local_index, bp_u32 k, float b1[3], float b2[3]) {
  bp_u32 row = 0u;
  while ((row + 1u) * (2u * k - row - 1u) <= local_index) ++row;
  bp_u32 in_row = local_index - row * (2u * k - row);
  bp_u32 col = in_row / 2u, upper = in_row % 2u;
  float inv_k = 1.0f / (float)k;
  float c = (float)col, r = (float)row;
  if (upper == 0u) {
    b1[0] = c * inv_k;          b2[0] = r * inv_k;
    b1[1] = (c + 1.0f) * inv_k; b2[1] = r * inv_k;
    b1[2] = c * inv_k;          b2[2] = (r + 1.0f) * inv_k;
  } else {
    b1[0] = (c + 1.0f) * inv_k; b2[0] = r * inv_k;
    b1[1] = (c + 1.0f) * inv_k; b2[1] = (r + 1.0f) * inv_k;
    b1[2] = c * inv_k;          b2[2] = (r + 1.0f) * inv_k;
  }
}

#endif  // BP_SHARED_PATCH_H

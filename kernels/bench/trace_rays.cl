// Benchmark kernel: closest hit for a fixed set of rays (BVH throughput without shading).
#include "shared/bvh.h"

// rays[2*i] = (origin.xyz, unused), rays[2*i+1] = (dir.xyz, unused); hits[i] = t, or -1 on a miss.
__kernel void trace_closest(__global const BvhNode* nodes, __global const BvhTriangle* triangles,
                            __global const float4* rays, const bp_u32 count, __global float* hits) {
  bp_u32 i = (bp_u32)get_global_id(0);
  if (i >= count) return;
  float4 o = rays[2 * i], d = rays[2 * i + 1];
  Hit hit;
  hits[i] = bvh_closest_hit(nodes, triangles, o.xyz, d.xyz, BP_FLOAT_MAX, &hit) ? hit.t : -1.0f;
}

// BVH traversal, one source for the path-tracing kernel (OpenCL C) and the host tests and
// benchmarks (C++). host/scene/bvh.cpp builds the tree (binned SAH, collapsed to 4-wide nodes);
// host/scene/bvh_layout_check.cpp static_asserts the layout of the structs below.
#ifndef BP_SHARED_BVH_H
#define BP_SHARED_BVH_H
#include "shared/compat.h"

// A child reference is an inner node's index, or BVH_LEAF | first << 3 | (count - 1): a run of
// `count` consecutive BvhTriangles. Node 0 is the root and always an inner node.
#define BVH_LEAF 0x80000000u
#define BVH_LEAF_COUNT_BITS 3u
#define BVH_LEAF_COUNT_MASK 7u
#define BVH_MAX_LEAF_TRIANGLES 8u
#define BVH_NO_TRIANGLE 0xffffffffu
#define BVH_NO_CHILD 0xffffffffu
// Entry distance of a child the ray misses; finite, so that fast-math builds keep the compares.
#define BVH_MISS 3.0e38f
// Each inner node on the path leaves at most 3 entries (and writes 3 more slots); the builder caps
// the depth at BVH_MAX_NODE_DEPTH nodes so 3 * depth + 1 <= BVH_STACK_SIZE.
#define BVH_STACK_SIZE 64
#define BVH_MAX_NODE_DEPTH 21

// Four children's boxes, SoA so one fetch feeds one 4-wide slab test:
// bounds[(2 * axis + side) * 4 + lane], side 0 = lo, 1 = hi. An unused lane has lo = +FLT_MAX,
// hi = -FLT_MAX, so no ray enters it. The builder pads every box by an ulp and 1e-20 on each side,
// so a ray running exactly along a face (a zero direction component, inverse clamped to 1e30)
// is strictly inside the slab and keeps the whole slab's extent.
typedef struct BP_ALIGN(64) {
  float bounds[24];
  bp_u32 child[4];
  bp_u32 pad[4];  // 128 bytes: two cache lines
} BvhNode;

// Triangle as the test wants it: p0, the edges from p0 and their cross product, in the original
// vertex order of Scene::triangles[triangle], so the test's barycentrics are the scene's.
typedef struct BP_ALIGN(64) {
  float v0[3];       // p0
  bp_u32 triangle;   // index in Scene::triangles
  float e1[3];       // p1 - p0
  float pad0;
  float e2[3];       // p2 - p0
  float pad1;
  float n[3];        // e1 x e2, not normalised
  float pad2;
} BvhTriangle;

typedef struct {
  float t;
  float b1;          // barycentric of p1: p = (1 - b1 - b2) p0 + b1 p1 + b2 p2
  float b2;
  bp_u32 triangle;   // index in Scene::triangles
} Hit;

// What the slab test needs of a ray, computed once per query.
typedef struct {
  float org[3];
  float inv[3];      // 1 / dir, finite: components are clamped away from zero to +-1e-30
  int near[3];       // offset in BvhNode::bounds of the entry plane of each axis (lo if dir >= 0)
} BvhRay;

BP_INLINE BvhRay bvh_make_ray(float3 origin, float3 dir) {
  BvhRay r;
  float d[3] = {dir.x, dir.y, dir.z};
  r.org[0] = origin.x; r.org[1] = origin.y; r.org[2] = origin.z;
  for (int a = 0; a < 3; ++a) {
    float da = fabs(d[a]) < 1e-30f ? (d[a] < 0.0f ? -1e-30f : 1e-30f) : d[a];
    r.inv[a] = 1.0f / da;
    r.near[a] = 8 * a + (da < 0.0f ? 4 : 0);
  }
  return r;
}

// Entry distance of the ray into each of the four children, BVH_MISS where it misses it or enters
// beyond t_far. Exit distances grow by 2 gamma_3 (Ize 2013) so rounding never loses a hit.
BP_INLINE bp_float4 bvh_node_entry(BP_GLOBAL const BvhNode* node, const BvhRay* r, float t_far) {
  BP_GLOBAL const float* b = node->bounds;
  bp_float4 ox = bp_splat4(r->org[0]), oy = bp_splat4(r->org[1]), oz = bp_splat4(r->org[2]);
  bp_float4 ix = bp_splat4(r->inv[0]), iy = bp_splat4(r->inv[1]), iz = bp_splat4(r->inv[2]);
  bp_float4 nx = (bp_load4(b + r->near[0]) - ox) * ix;
  bp_float4 ny = (bp_load4(b + r->near[1]) - oy) * iy;
  bp_float4 nz = (bp_load4(b + r->near[2]) - oz) * iz;
  bp_float4 fx = (bp_load4(b + (r->near[0] ^ 4)) - ox) * ix;
  bp_float4 fy = (bp_load4(b + (r->near[1] ^ 4)) - oy) * iy;
  bp_float4 fz = (bp_load4(b + (r->near[2] ^ 4)) - oz) * iz;
  bp_float4 entry = bp_max4(bp_max4(nx, ny), bp_max4(nz, bp_splat4(0.0f)));
  bp_float4 t_exit = bp_min4(bp_min4(fx, fy), bp_min4(fz, bp_splat4(t_far))) * bp_splat4(1.0000004f);
  return entry <= t_exit ? entry : bp_splat4(BVH_MISS);
}

// Starts fetching every child (both lines of a node, every triangle of a leaf) while the slab
// test runs: traversal is bound by memory latency once the tree outgrows L2 (+10% at 100k
// triangles, +30% at 1M on PoCL).
BP_INLINE void bvh_prefetch_children(BP_GLOBAL const BvhNode* nodes, BP_GLOBAL const BvhTriangle* tris,
                                     BP_GLOBAL const BvhNode* node) {
  for (int lane = 0; lane < 4; ++lane) {
    bp_u32 ref = node->child[lane];
    if (ref & BVH_LEAF) {
      BP_GLOBAL const BvhTriangle* tri = tris + ((ref & ~BVH_LEAF) >> BVH_LEAF_COUNT_BITS);
      for (bp_u32 i = 0; i <= (ref & BVH_LEAF_COUNT_MASK); ++i) BP_PREFETCH((BP_GLOBAL const char*)(tri + i));
    } else {
      BP_GLOBAL const char* line = (BP_GLOBAL const char*)(nodes + ref);
      BP_PREFETCH(line);
      BP_PREFETCH(line + 64);
    }
  }
}

// Ray-triangle test (Moller-Trumbore with the normal precomputed, as Embree's): with c = p0 - o,
// r = c x d and det = d . n, the hit is t = c . n / det, b1 = r . e2 / det, b2 = -r . e1 / det.
// Scalar on purpose: as float3 PoCL spends its time on horizontal adds. On a hit with
// 0 < t < *t it overwrites *t, *b1, *b2 and returns 1.
BP_INLINE int bvh_intersect_triangle(BP_GLOBAL const BvhTriangle* tri, float3 origin, float3 dir,
                                     float* t, float* b1, float* b2) {
  float cx = tri->v0[0] - origin.x, cy = tri->v0[1] - origin.y, cz = tri->v0[2] - origin.z;
  float nx = tri->n[0], ny = tri->n[1], nz = tri->n[2];
  float rx = cy * dir.z - cz * dir.y, ry = cz * dir.x - cx * dir.z, rz = cx * dir.y - cy * dir.x;
  float det = dir.x * nx + dir.y * ny + dir.z * nz;
  float sign = det < 0.0f ? -1.0f : 1.0f;
  float abs_det = det * sign;
  float u = (rx * tri->e2[0] + ry * tri->e2[1] + rz * tri->e2[2]) * sign;
  float v = -(rx * tri->e1[0] + ry * tri->e1[1] + rz * tri->e1[2]) * sign;
  float tt = (cx * nx + cy * ny + cz * nz) * sign;
  if (u >= 0.0f && v >= 0.0f && u + v <= abs_det && tt > 0.0f && tt < *t * abs_det) {
    float inv_det = 1.0f / abs_det;
    float t_hit = tt * inv_det;
    if (t_hit < *t) {
      *t = t_hit;
      *b1 = u * inv_det;
      *b2 = v * inv_det;
      return 1;
    }
  }
  return 0;
}

// Compare-exchange: afterwards *da <= *db, child references moved along. Branch-free.
BP_INLINE void bvh_order(float* da, bp_u32* ca, float* db, bp_u32* cb) {
  float a = *da, b = *db;
  bp_u32 x = *ca, y = *cb;
  int swap = b < a;
  *da = swap ? b : a;
  *db = swap ? a : b;
  *ca = swap ? y : x;
  *cb = swap ? x : y;
}

// Returns the nearest child the ray enters (BVH_NO_CHILD if none) and pushes the others, farthest
// deepest. One child (about half the visits): no sorting. More: a branch-free sorting network,
// as mispredicted branches cost more than the network on incoherent rays. Writes up to 3 slots
// above *sp whether or not they are kept.
BP_INLINE bp_u32 bvh_visit_children(BP_GLOBAL const BvhNode* node, bp_float4 entry, bp_u32* stack_ref,
                                    float* stack_t, int* sp) {
  float d0 = BP_LANE(entry, 0), d1 = BP_LANE(entry, 1);
  float d2 = BP_LANE(entry, 2), d3 = BP_LANE(entry, 3);
  bp_u32 c0 = node->child[0], c1 = node->child[1], c2 = node->child[2], c3 = node->child[3];
  int hits = (d0 < BVH_MISS ? 1 : 0) + (d1 < BVH_MISS ? 1 : 0) + (d2 < BVH_MISS ? 1 : 0) + (d3 < BVH_MISS ? 1 : 0);
  if (hits <= 1)
    return d0 < BVH_MISS ? c0 : d1 < BVH_MISS ? c1 : d2 < BVH_MISS ? c2 : d3 < BVH_MISS ? c3 : BVH_NO_CHILD;
  bvh_order(&d0, &c0, &d1, &c1);  // sorting network for 4
  bvh_order(&d2, &c2, &d3, &c3);
  bvh_order(&d0, &c0, &d2, &c2);
  bvh_order(&d1, &c1, &d3, &c3);
  bvh_order(&d1, &c1, &d2, &c2);
  int top = *sp;
  stack_ref[top] = c3; stack_t[top] = d3; top += d3 < BVH_MISS ? 1 : 0;
  stack_ref[top] = c2; stack_t[top] = d2; top += d2 < BVH_MISS ? 1 : 0;
  stack_ref[top] = c1; stack_t[top] = d1; top += d1 < BVH_MISS ? 1 : 0;
  *sp = top;
  return c0;
}

// Nearest hit with 0 < t < t_max; dir unit length. Returns 1 and fills *hit if there is one.
BP_FN int bvh_closest_hit(BP_GLOBAL const BvhNode* nodes, BP_GLOBAL const BvhTriangle* tris,
                          float3 origin, float3 dir, float t_max, Hit* hit) {
  BvhRay ray = bvh_make_ray(origin, dir);
  bp_u32 stack_ref[BVH_STACK_SIZE];
  float stack_t[BVH_STACK_SIZE];
  int sp = 0;
  bp_u32 ref = 0u;
  float t = t_max, b1 = 0.0f, b2 = 0.0f;
  bp_u32 found = BVH_NO_TRIANGLE;
  for (;;) {
    if ((ref & BVH_LEAF) == 0u) {
      BP_GLOBAL const BvhNode* node = nodes + ref;
      bvh_prefetch_children(nodes, tris, node);
      ref = bvh_visit_children(node, bvh_node_entry(node, &ray, t), stack_ref, stack_t, &sp);
      if (ref != BVH_NO_CHILD) continue;
    } else {
      bp_u32 first = (ref & ~BVH_LEAF) >> BVH_LEAF_COUNT_BITS;
      bp_u32 end = first + (ref & BVH_LEAF_COUNT_MASK) + 1u;
      for (bp_u32 i = first; i < end; ++i)
        if (bvh_intersect_triangle(tris + i, origin, dir, &t, &b1, &b2)) found = i;
    }
    // pop the nearest pending child the ray still reaches before t
    int popped = 0;
    while (sp > 0) {
      --sp;
      if (stack_t[sp] < t) {
        ref = stack_ref[sp];
        popped = 1;
        break;
      }
    }
    if (!popped) break;
  }
  if (found == BVH_NO_TRIANGLE) return 0;
  hit->t = t;
  hit->b1 = b1;
  hit->b2 = b2;
  hit->triangle = tris[found].triangle;
  return 1;
}

// Whether anything lies along the ray with 0 < t < t_max; dir unit length. Stops at the first hit.
// Near-first order pays here too: the nearer blocker is found with fewer visits.
BP_FN int bvh_occluded(BP_GLOBAL const BvhNode* nodes, BP_GLOBAL const BvhTriangle* tris,
                       float3 origin, float3 dir, float t_max) {
  BvhRay ray = bvh_make_ray(origin, dir);
  bp_u32 stack_ref[BVH_STACK_SIZE];
  float stack_t[BVH_STACK_SIZE];
  int sp = 0;
  bp_u32 ref = 0u;
  for (;;) {
    if ((ref & BVH_LEAF) == 0u) {
      BP_GLOBAL const BvhNode* node = nodes + ref;
      bvh_prefetch_children(nodes, tris, node);
      ref = bvh_visit_children(node, bvh_node_entry(node, &ray, t_max), stack_ref, stack_t, &sp);
      if (ref != BVH_NO_CHILD) continue;
    } else {
      bp_u32 first = (ref & ~BVH_LEAF) >> BVH_LEAF_COUNT_BITS;
      bp_u32 end = first + (ref & BVH_LEAF_COUNT_MASK) + 1u;
      float t = t_max, b1, b2;
      for (bp_u32 i = first; i < end; ++i)
        if (bvh_intersect_triangle(tris + i, origin, dir, &t, &b1, &b2)) return 1;
    }
    if (sp == 0) return 0;
    ref = stack_ref[--sp];
  }
}

#endif  // BP_SHARED_BVH_H

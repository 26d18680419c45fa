// The kernel compiles the same BVH structs as OpenCL C: no implicit padding, sizes multiples of 16.
#include "kernels/shared/bvh.h"

#include <cstddef>

static_assert(sizeof(BvhNode) == 128 && sizeof(BvhNode) % 16 == 0);
static_assert(offsetof(BvhNode, bounds) == 0);
static_assert(offsetof(BvhNode, child) == 96);
static_assert(offsetof(BvhNode, pad) == 112);

static_assert(sizeof(BvhTriangle) == 64);
static_assert(offsetof(BvhTriangle, v0) == 0);
static_assert(offsetof(BvhTriangle, triangle) == 12);
static_assert(offsetof(BvhTriangle, e1) == 16);
static_assert(offsetof(BvhTriangle, e2) == 32);
static_assert(offsetof(BvhTriangle, n) == 48);

static_assert(sizeof(Hit) == 16);
static_assert(offsetof(Hit, t) == 0 && offsetof(Hit, b1) == 4 && offsetof(Hit, b2) == 8);
static_assert(offsetof(Hit, triangle) == 12);

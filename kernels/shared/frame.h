// Orthonormal frames around a unit vector (Duff et al., "Building an orthonormal basis, revisited",
// JCGT 2017): branchless and stable for every n.
#ifndef BP_SHARED_FRAME_H
#define BP_SHARED_FRAME_H
#include "shared/compat.h"

typedef struct { float3 t, b, n; } Frame;

BP_FN Frame frame_from_normal(float3 n) {
  float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (sign + n.z);
  float b = n.x * n.y * a;
  Frame f;
  f.t = make_float3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  f.b = make_float3(b, sign + n.y * n.y * a, -n.y);
  f.n = n;
  return f;
}

BP_FN float3 frame_to_world(const Frame* f, float3 v) {
  return f->t * v.x + f->b * v.y + f->n * v.z;
}

// Mirror of w about n (both unit, w pointing away from the surface).
BP_FN float3 reflect_about(float3 w, float3 n) { return n * (2.0f * dot(n, w)) - w; }

#endif  // BP_SHARED_FRAME_H

// Pinhole camera rays; the path tracer and the ray-bundle eye pass use the same jittered rays,
// so both estimate the same pixel integral (docs/design.md §4).
#ifndef BP_SHARED_CAMERA_H
#define BP_SHARED_CAMERA_H
#include "shared/compat.h"
#include "shared/types.h"

// Unit direction through pixel (px, py) (py = 0 is the top row) at sub-pixel jitter (jx, jy) in [0,1).
BP_FN float3 camera_ray_direction(const CameraParams* c, bp_u32 px, bp_u32 py, float jx, float jy) {
  float sx = (2.0f * ((float)px + jx) / (float)c->width - 1.0f) * c->tan_half_fov_x;
  float sy = (1.0f - 2.0f * ((float)py + jy) / (float)c->height) * c->tan_half_fov_y;
  float3 d = make_float3(c->forward[0], c->forward[1], c->forward[2]) +
             make_float3(c->right[0], c->right[1], c->right[2]) * sx +
             make_float3(c->up[0], c->up[1], c->up[2]) * sy;
  return normalize(d);
}

#endif  // BP_SHARED_CAMERA_H

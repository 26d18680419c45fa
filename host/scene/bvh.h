// Binned-SAH BVH, built on the host and flattened for kernels/shared/bvh.h.
#pragma once
#include "kernels/shared/bvh.h"
#include "scene/scene.h"
#include <vector>

namespace bp {

struct FlatBvh {
  std::vector<BvhNode> nodes;          // nodes[0] is the root
  std::vector<BvhTriangle> triangles;  // leaf order; each remembers its index in Scene::triangles
};

FlatBvh build_bvh(const std::vector<SceneTriangle>& triangles);

// Whether the segment from origin along unit dir reaches `distance` (BP_FLOAT_MAX: leaves the scene)
// unblocked, thin panes passing it (docs/design.md §11: a sun reaches a room through its windows), at most
// BP_MAX_PANE_CROSSINGS of them; `step` metres short of the end and past each pane. The host's
// visibility for the light tree's receivers and the patches' refinement.
bool clear_through_panes(const FlatBvh& bvh, const Scene& scene, float3 origin, float3 dir, float distance,
                         float step);

}  // namespace bp

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

}  // namespace bp

// The fixed incoherent ray set of the BVH benchmarks: camera rays through a 256 x 192 grid, then
// from each camera hit one cosine-distributed bounce. Both kinds are counted as rays.
#pragma once
#include "scene/bvh.h"
#include "scene/scene.h"
#include <vector>

namespace bp::bench {

struct RaySet {
  std::vector<float3> origin, dir;
};

RaySet make_rays(const Scene& scene, const FlatBvh& bvh);

}  // namespace bp::bench

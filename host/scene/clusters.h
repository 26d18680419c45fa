// Patch clusters (docs/design.md §12): neighbouring triangles of one plain material that lie in one plane
// and whose union is a convex polygon are merged into that polygon, so the ray-bundle pass sees the
// surface, not its tessellation. The polygon is written as a fan of triangles that own the cluster's
// patches (patches.h); the scene's triangles stay what the path tracer and the BVH see.
#pragma once
#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace bp {

// A cluster's outline has at most this many corners (so a fan of at most kMaxClusterCorners - 2
// triangles, which the path tracer searches for its hit's patch: kernels/shared/patch.h).
inline constexpr std::uint32_t kMaxClusterCorners = 8;

struct PatchClusters {
  std::vector<SceneTriangle> fans;           // each cluster's outline as a fan, clusters one after the other
  std::vector<std::uint32_t> fan_source;     // per fan triangle: one scene triangle of its cluster
  std::vector<std::uint32_t> fan_first;      // per scene triangle: its cluster's first fan triangle
  std::vector<std::uint32_t> fan_count;      // per scene triangle: its cluster's fan triangles; 0: no cluster
  std::size_t clusters = 0;                  // of two or more triangles (a lone triangle stays itself)
  std::size_t clustered_triangles = 0;
};

// Whether triangle t may join a cluster: a flat, opaque, untextured, non-emissive surface (the patch
// reads nothing per triangle), with NORMAL corners, if any, equal to its flat normal.
bool clusterable_triangle(const Scene& scene, std::size_t t);

// Clusters grown greedily from each unclustered triangle in index order (deterministic): a neighbour
// across a shared edge joins when it is clusterable, of the same material, in the plane (normals within
// 0.06 degrees, corners within 1e-5 of the scene's diagonal), and the union stays a convex polygon of at
// most kMaxClusterCorners corners and diameter max_size (metres).
PatchClusters build_patch_clusters(const Scene& scene, float max_size);

}  // namespace bp

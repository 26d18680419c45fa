// The scene on the device: BVH, per-triangle shading records and materials, packed into the
// structs of kernels/shared/types.h and uploaded once.
#pragma once
#include "device/device_context.h"
#include "scene/bvh.h"
#include "scene/light_tree.h"
#include "scene/lights.h"
#include "scene/patches.h"
#include "scene/scene.h"
#include "kernels/shared/types.h"
#include <vector>

namespace bp {

// Host-side packing, separate from upload so it can be tested without a device.
std::vector<Material> pack_materials(const Scene& scene, const LightList& lights);
std::vector<TriangleShading> pack_triangle_shading(const Scene& scene, const PatchLayout& patches);
// The clusters' fan triangles (kernels/shared/cluster.h), in PatchLayout's order.
std::vector<ClusterFan> pack_cluster_fans(const Scene& scene, const PatchLayout& patches);
// Per triangle its three corners' shading normals (9 floats, front side; the flat normal where the
// triangle has no NORMAL), or nothing when no triangle has them (the kernels then never read them).
std::vector<float> pack_shading_normals(const Scene& scene);
// Per triangle its three corners' TANGENT (12 floats: xyz w), or nothing when no material has a
// normal map (kernels/shared/normal_map.h reads them for normal-mapped materials only).
std::vector<float> pack_tangents(const Scene& scene);
CameraParams pack_camera(const SceneCamera& camera, int width, int height);
// Offset for secondary rays: relative to the scene's size and coordinate magnitude, so it works at
// every scale (1e-3 to 1e4 m).
float ray_epsilon_for(const Bounds& bounds);

struct DeviceScene {
  cl::Buffer nodes, triangles, shading, materials;
  cl::Buffer cluster_fans;  // pack_cluster_fans (one dummy entry without clusters)
  cl::Buffer lights, light_cdf;  // one dummy entry each when the scene has no light to sample
  cl::Buffer shading_normals;  // pack_shading_normals (one dummy entry without them)
  std::uint32_t has_shading_normals = 0;  // 1: the kernels interpolate shading_normals
  cl::Buffer tangents;  // pack_tangents (one dummy entry without normal maps)
  // Textures (host/scene/textures.h; one dummy entry each without them): views, RGBA8 texels, each
  // material's textures, per-triangle texcoords, and per patch its mean material.
  cl::Buffer texture_views, texels, material_textures, texcoords, patch_materials;
  std::uint32_t uv_slots = 0;  // texcoord sets per triangle; 0: the scene has no textures
  std::uint32_t alpha_masks = 0;  // 1: some material has alphaMode MASK (kernels/shared/alpha_mask.h)
  cl::Buffer element_triangle, element_coverage;  // alpha masks: per RB element its triangle and surface fraction
  std::size_t texture_bytes = 0;  // of the above, device memory (in `bytes` too)
  // The environment map with its sampling cdfs (host/scene/environment_map.h; one dummy float
  // without one), its size (0 x 0: none) and its light's index (BP_NO_LIGHT: none to sample).
  cl::Buffer environment;
  std::uint32_t environment_width = 0, environment_height = 0, environment_light = BP_NO_LIGHT;
  std::size_t environment_bytes = 0;  // of the above, device memory (in `bytes` too)
  cl::Buffer light_tree, light_receivers;  // tree selection only (else one dummy entry each); receivers per patch
  std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE;  // BP_LIGHT_SELECTION_*, the same for PT and RB
  std::size_t triangle_count = 0, node_count = 0;
  std::uint32_t light_count = 0;
  float delta_light_share = 0.0f;  // of the lights' selection power: point, spot and directional lights'
  float ray_epsilon = 0.0f;  // ray_epsilon_for(the scene's bounds)
  std::size_t bytes = 0;  // device memory held
  DeviceScene(const DeviceContext& device, const Scene& scene, const PatchLayout& patches, const FlatBvh& bvh,
              std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE);
};

}  // namespace bp

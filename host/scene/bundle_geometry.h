// The geometry the ray-bundle pass needs (docs/design.md §4): every sub-triangle of the patch grid as an
// element with its corners, normal, area and the patches of its two sides.
#pragma once
#include "kernels/shared/bundle_types.h"
#include "scene/patches.h"
#include "scene/scene.h"
#include <cstdint>
#include <vector>

namespace bp {

// Top bit of patch_element: the patch is the back side of its element.
constexpr std::uint32_t kBackSidePatch = 0x80000000u;

struct BundleGeometry {
  std::vector<BundleElement> elements;       // triangle t's elements start at first_element[t]
  std::vector<std::uint32_t> first_element;  // per triangle
  std::vector<std::uint32_t> patch_element;  // per patch: its element, | kBackSidePatch for a back side
  // Gouraud vertices (docs/design.md §4): patch corners welded where patches of one material and one
  // facing meet at the same point; a vertex holds the area-weighted mean of its patches' E_in.
  std::vector<std::uint32_t> patch_vertices;      // 3 per patch, in the element's corner order
  std::vector<std::uint32_t> vertex_patch_start;  // CSR: patches of vertex v are
  std::vector<std::uint32_t> vertex_patches;      //   vertex_patches[vertex_patch_start[v] .. [v+1])
  double element_area = 0.0;                 // sum of element areas (each surface counted once), m^2
  double element_perimeter = 0.0;            // sum of element perimeters, m
  glm::vec3 centre{0.0f};                    // bounding sphere of the scene
  float radius = 0.0f;
};

// What sizes the ray-bundle pass, known before the geometry is built (so a run that cannot fit is
// refused before anything large is allocated).
struct BundleSize {
  std::size_t elements = 0, patches = 0;
  double element_area = 0.0;  // m^2, each surface once
  double element_perimeter = 0.0;  // m, sum over elements (what bounds the fragments one can cover)
  float radius = 0.0f;        // of the scene's bounding sphere
};
BundleSize bundle_size(const Scene& scene, const PatchLayout& patches);
BundleSize bundle_size(const BundleGeometry& geometry);  // the same numbers, from the built geometry

BundleGeometry build_bundle_geometry(const Scene& scene, const PatchLayout& patches);

}  // namespace bp

#include "scene/bundle_geometry.h"

#include <cmath>
#include <unordered_map>

namespace bp {

namespace {

float bounding_radius(const Scene& scene) { return 0.5f * glm::length(scene.bounds.extent()) * 1.001f + 1e-6f; }

// Corners are welded when position (to 1e-6 of the scene), facing normal (to 1e-4) and material agree.
struct CornerKey {
  std::int64_t p[3];
  std::int32_t n[3];
  std::uint32_t material;
  bool operator==(const CornerKey&) const = default;
};

struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const {
    std::uint64_t h = 0xcbf29ce484222325ull;
    auto mix = [&](std::uint64_t v) { h = (h ^ v) * 0x100000001b3ull; };
    for (auto v : k.p) mix(std::uint64_t(v));
    for (auto v : k.n) mix(std::uint64_t(std::uint32_t(v)));
    mix(k.material);
    return std::size_t(h);
  }
};

void weld_vertices(const Scene& scene, BundleGeometry& g) {
  const double quantum = std::max(1e-6 * double(glm::length(scene.bounds.extent())), 1e-12);
  std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> ids;
  std::vector<std::uint32_t> vertex_of_slot;
  g.patch_vertices.assign(g.patch_element.size() * 3, 0u);
  for (std::size_t p = 0; p < g.patch_element.size(); ++p) {
    const BundleElement& el = g.elements[g.patch_element[p] & ~kBackSidePatch];
    const float side = (g.patch_element[p] & kBackSidePatch) ? -1.0f : 1.0f;
    const glm::vec3 v0(el.v0[0], el.v0[1], el.v0[2]), e1(el.e1[0], el.e1[1], el.e1[2]), e2(el.e2[0], el.e2[1], el.e2[2]);
    const glm::vec3 corners[3] = {v0, v0 + e1, v0 + e2};
    for (int c = 0; c < 3; ++c) {
      CornerKey key{};
      for (int i = 0; i < 3; ++i) {
        key.p[i] = std::llround(double(corners[c][i]) / quantum);
        key.n[i] = std::int32_t(std::lround(side * el.normal[i] * 1e4));
      }
      key.material = el.material;
      auto [it, inserted] = ids.try_emplace(key, std::uint32_t(ids.size()));
      g.patch_vertices[p * 3 + c] = it->second;
    }
  }
  // CSR adjacency vertex -> patches.
  const std::size_t vertices = ids.size();
  g.vertex_patch_start.assign(vertices + 1, 0u);
  for (std::uint32_t v : g.patch_vertices) ++g.vertex_patch_start[v + 1];
  for (std::size_t v = 0; v < vertices; ++v) g.vertex_patch_start[v + 1] += g.vertex_patch_start[v];
  g.vertex_patches.assign(g.patch_vertices.size(), 0u);
  std::vector<std::uint32_t> cursor(g.vertex_patch_start.begin(), g.vertex_patch_start.end() - 1);
  for (std::size_t i = 0; i < g.patch_vertices.size(); ++i)
    g.vertex_patches[cursor[g.patch_vertices[i]]++] = std::uint32_t(i / 3);
}

}  // namespace

BundleSize bundle_size(const Scene& scene, const PatchLayout& patches) {
  BundleSize size;
  size.patches = patches.patch_count;
  for (std::size_t t = 0; t < patch_triangle_count(scene, patches); ++t) {
    if (patches.subdiv[t] == 0) continue;  // clustered: its fan has its area
    const SceneTriangle& tri = patch_triangle(scene, patches, t);
    size.elements += std::size_t(patches.subdiv[t]) * patches.subdiv[t];
    size.element_area += 0.5 * double(glm::length(glm::cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0])));
    // k^2 congruent sub-triangles, each with 1/k of the triangle's perimeter
    size.element_perimeter += double(patches.subdiv[t]) * (double(glm::length(tri.p[1] - tri.p[0])) +
                                                            glm::length(tri.p[2] - tri.p[1]) +
                                                            glm::length(tri.p[0] - tri.p[2]));
  }
  size.radius = bounding_radius(scene);
  return size;
}

BundleSize bundle_size(const BundleGeometry& geometry) {
  return BundleSize{geometry.elements.size(), geometry.patch_element.size(), geometry.element_area,
                    geometry.element_perimeter, geometry.radius};
}

BundleGeometry build_bundle_geometry(const Scene& scene, const PatchLayout& patches) {
  BundleGeometry g;
  g.patch_element.assign(patches.patch_count, 0u);
  g.first_element.resize(patch_triangle_count(scene, patches));
  std::size_t element_count = 0;
  for (std::size_t t = 0; t < g.first_element.size(); ++t) {
    g.first_element[t] = std::uint32_t(element_count);
    element_count += std::size_t(patches.subdiv[t]) * patches.subdiv[t];
  }
  g.elements.resize(element_count);
  for_each_sub_triangle(scene, patches, [&](const SubTriangle& sub) {
    const SceneTriangle& tri = *sub.parent;
    glm::vec3 c[3];
    for (int i = 0; i < 3; ++i) c[i] = tri.p[0] + sub.b1[i] * sub.e1 + sub.b2[i] * sub.e2;
    const std::uint32_t index = g.first_element[sub.triangle] + sub.local;
    BundleElement& el = g.elements[index];
    el = BundleElement{};
    const glm::vec3 d1 = c[1] - c[0], d2 = c[2] - c[0];
    for (int i = 0; i < 3; ++i) {
      el.v0[i] = c[0][i];
      el.e1[i] = d1[i];
      el.e2[i] = d2[i];
      el.normal[i] = sub.normal[i];
    }
    el.area = 0.5f * sub.parent_area2 / float(sub.k2);  // congruent sub-triangles: exactly 1/k^2 of the parent
    el.material = tri.material;
    el.front_patch = patches.first_patch[sub.triangle] + sub.local;
    el.back_patch = sub.double_sided ? patches.first_patch[sub.triangle] + sub.k2 + sub.local : BP_NO_PATCH;
    g.patch_element[el.front_patch] = index;
    if (sub.double_sided) g.patch_element[el.back_patch] = index | kBackSidePatch;
    g.element_area += el.area;
    g.element_perimeter += double(glm::length(d1)) + glm::length(d2) + glm::length(d2 - d1);
  });
  weld_vertices(scene, g);
  g.centre = scene.bounds.centre();
  g.radius = bounding_radius(scene);
  return g;
}

}  // namespace bp

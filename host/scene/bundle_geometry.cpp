#include "scene/bundle_geometry.h"
#include "kernels/shared/patch.h"

namespace bp {

BundleGeometry build_bundle_geometry(const Scene& scene, const PatchLayout& patches) {
  BundleGeometry g;
  g.patch_element.assign(patches.patch_count, 0u);
  g.first_element.resize(scene.triangles.size());
  std::size_t element_count = 0;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    g.first_element[t] = std::uint32_t(element_count);
    element_count += std::size_t(patches.subdiv[t]) * patches.subdiv[t];
  }
  g.elements.resize(element_count);
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const SceneTriangle& tri = scene.triangles[t];
    const std::uint32_t k = patches.subdiv[t], k2 = k * k;
    const bool double_sided = scene.materials[tri.material].double_sided;
    const glm::vec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
    glm::vec3 n = glm::cross(e1, e2);
    const float len = glm::length(n);
    n = len > 0.0f ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
    for (std::uint32_t local = 0; local < k2; ++local) {
      float b1[3], b2[3];
      patch_corner_barycentrics(local, k, b1, b2);
      glm::vec3 c[3];
      for (int i = 0; i < 3; ++i) c[i] = tri.p[0] + b1[i] * e1 + b2[i] * e2;
      const std::uint32_t index = g.first_element[t] + local;
      BundleElement& el = g.elements[index];
      el = BundleElement{};
      const glm::vec3 d1 = c[1] - c[0], d2 = c[2] - c[0];
      for (int i = 0; i < 3; ++i) {
        el.v0[i] = c[0][i];
        el.e1[i] = d1[i];
        el.e2[i] = d2[i];
        el.normal[i] = n[i];
      }
      el.area = 0.5f * len / float(k2);  // congruent sub-triangles: exactly 1/k^2 of the parent
      el.material = tri.material;
      el.front_patch = patches.first_patch[t] + local;
      el.back_patch = double_sided ? patches.first_patch[t] + k2 + local : BP_NO_PATCH;
      g.patch_element[el.front_patch] = index;
      if (double_sided) g.patch_element[el.back_patch] = index | kBackSidePatch;
      g.element_area += el.area;
    }
  }
  g.centre = scene.bounds.centre();
  g.radius = 0.5f * glm::length(scene.bounds.extent()) * 1.001f + 1e-6f;
  return g;
}

}  // namespace bp

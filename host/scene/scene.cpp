#include "scene/scene.h"

#include <algorithm>

namespace bp {

std::size_t Scene::emissive_triangles() const {
  return std::size_t(std::count_if(triangles.begin(), triangles.end(), [&](const SceneTriangle& t) {
    const glm::vec3 le = materials.at(t.material).emission;
    return le.x > 0.0f || le.y > 0.0f || le.z > 0.0f;
  }));
}

bool Scene::has_shading_normals() const {
  return std::any_of(triangles.begin(), triangles.end(), [](const SceneTriangle& t) { return t.has_normals; });
}

}  // namespace bp

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
  return has_normal_maps() ||
         std::any_of(triangles.begin(), triangles.end(), [](const SceneTriangle& t) { return t.has_normals; });
}

bool Scene::has_textures() const {
  return std::any_of(materials.begin(), materials.end(),
                     [](const SceneMaterial& m) { return m.textured() || m.has_normal_map(); });
}

bool Scene::has_normal_maps() const {
  return std::any_of(materials.begin(), materials.end(), [](const SceneMaterial& m) { return m.has_normal_map(); });
}

bool Scene::has_alpha_masks() const {
  return std::any_of(materials.begin(), materials.end(),
                     [](const SceneMaterial& m) { return m.textured() && m.textures.alpha_cutoff > 0.0f; });
}

bool Scene::has_transmission() const {
  return std::any_of(materials.begin(), materials.end(), [](const SceneMaterial& m) { return m.transmission > 0.0f; });
}

MaterialTextures SceneMaterial::untextured() {
  MaterialTextures t{};
  t.base_color = t.metallic_roughness = t.emissive = t.normal = t.specular = t.specular_color = BP_NO_TEXTURE;
  t.normal_scale = 1.0f;
  t.alpha_cutoff = 0.0f;
  for (float& c : t.base_color_factor) c = 1.0f;
  t.metallic_factor = t.roughness_factor = 1.0f;
  return t;
}

}  // namespace bp

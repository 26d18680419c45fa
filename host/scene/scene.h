// The scene as the renderer sees it, independent of file format and of OpenCL.
#pragma once
#include "kernels/shared/texture.h"
#include "scene/environment_map.h"
#include "scene/scene_cameras.h"
#include <glm/glm.hpp>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bp {

struct SceneMaterial {
  std::string name;
  glm::vec3 kd{0.8f};          // diffuse albedo
  glm::vec3 ks{0.0f};          // specular albedo
  float shininess = 1.0f;      // Phong exponent n
  glm::vec3 emission{0.0f};    // radiance Le, W sr^-1 m^-2 (front side; both if double_sided)
  bool double_sided = false;
  // KHR_materials_transmission, thin-walled (docs/design.md §11): the share `transmission` of the surface is
  // a pane that passes (1 - F) transmission_tint straight through and mirrors F transmission, F by the
  // ior (kernels/shared/thin_glass.h); the opaque rest is scaled by 1 - transmission (kd and ks here;
  // a GGX material's f in the kernels).
  float transmission = 0.0f;
  glm::vec3 transmission_tint{1.0f};  // baseColor (factor): the pane's colour
  float ior = 1.5f;
  // KHR_materials_volume with thickness > 0: the transmitted share refracts into the mesh's medium
  // (kernels/shared/dielectric.h), which attenuates by exp(-attenuation d) over d metres.
  bool volume = false;
  glm::vec3 attenuation{0.0f};  // m^-1
  // glTF's metallic-roughness BRDF (kernels/shared/metallic_roughness.h) when `ggx`; kd, ks and
  // shininess are then unused. Without it the material is Modified Phong (extras.phong, Lambert).
  bool ggx = false;
  glm::vec3 base_color{1.0f};
  float metallic = 1.0f;
  float roughness = 1.0f;              // perceptual; the GGX alpha is its square
  glm::vec3 dielectric_f0{0.04f};      // min(((ior - 1)/(ior + 1))^2 specularColor, 1)
  float specular_weight = 1.0f;        // KHR_materials_specular's specular
  // glTF textures and the factors they multiply (kernels/shared/texture.h); base colour, metallic,
  // roughness, emission (and kd of a Lambert one) above are the factors' values, what the material
  // is where no texture says otherwise.
  MaterialTextures textures = untextured();
  bool textured() const { return material_is_textured(&textures); }      // f or emission has textures
  bool has_normal_map() const { return material_has_normal_map(&textures); }
  static MaterialTextures untextured();
};

struct SceneTriangle {
  glm::vec3 p[3];              // world space, metres, counter-clockwise = front
  std::uint32_t material = 0;
  // glTF NORMAL at the corners, world space, unit, front side; interpolated for shading (docs/design.md §6)
  bool has_normals = false;
  glm::vec3 normal[3]{};
  // TEXCOORD corners of the texcoord sets the material's textures read (TextureView::uv_slot)
  glm::vec2 uv[BP_MAX_UV_SLOTS][3]{};
  // Where the material has a normal map: TANGENT at the corners (xyz world space, unit, orthogonal to
  // `normal`; w the handedness +-1), from the file or generated (kernels/shared/normal_map.h)
  glm::vec4 tangent[3]{};
};

// A KHR_lights_punctual light. glTF gives intensity in candela (point, spot) or lux (directional);
// the loader converts it to radiant intensity (W sr^-1) or irradiance (W m^-2) at 683 lm/W. No range
// cut-off: the inverse square law everywhere.
struct ScenePunctualLight {
  enum class Kind { point, spot, directional };
  Kind kind = Kind::point;
  std::string name;
  glm::vec3 position{0.0f};                // point, spot
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // unit; spot: the cone's axis; directional: where the light travels
  glm::vec3 intensity{1.0f};               // colour times intensity: W sr^-1 (point, spot), W m^-2 (directional)
  float inner_cone = 0.0f;                 // spot: radians, full intensity within
  float outer_cone = 0.7853982f;           // spot: radians, no light beyond
};

struct Bounds {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{-std::numeric_limits<float>::max()};
  void grow(const glm::vec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
  glm::vec3 extent() const { return hi - lo; }
  glm::vec3 centre() const { return 0.5f * (lo + hi); }
};

struct Scene {
  std::string source;                    // file it came from
  std::vector<SceneTriangle> triangles;
  std::vector<SceneMaterial> materials;  // index 0: the default material; file material i is at i + 1
  std::vector<ScenePunctualLight> lights;
  // Textures: every image's RGBA8 texels (kernels/shared/texture.h), and one view per use of an
  // image by a material (TextureView::first_texel indexes texels).
  std::vector<std::uint32_t> texels;
  std::vector<TextureView> texture_views;
  std::uint32_t uv_slots = 0;            // texcoord sets per triangle that textures read (<= BP_MAX_UV_SLOTS)
  glm::vec3 environment{0.0f};           // uniform radiance of every direction that leaves the scene, W sr^-1 m^-2
  // --environment FILE.exr: radiance by direction (wins over `environment`); shared, as copies of a
  // scene never change it and a map may hold hundreds of MB
  std::shared_ptr<const EnvironmentImage> environment_image;
  SceneCamera camera;                    // the view of a plain render: the first camera node's, else a default
  std::vector<SceneCameraNode> camera_nodes;  // every perspective camera node, in traversal order
  std::vector<std::string> node_names;   // every node of the file, by index ("" if unnamed)
  Bounds bounds;
  std::vector<std::string> warnings;     // things the loader accepted but a user should know
  std::size_t emissive_triangles() const;
  bool has_shading_normals() const;      // some triangle has NORMAL corners, or some material a normal map
  bool has_textures() const;             // some material has a texture
  bool has_normal_maps() const;          // some material has a normalTexture
  bool has_alpha_masks() const;          // some material has alphaMode MASK with a texture
  bool has_transmission() const;         // some material transmits (a thin pane or a refractor)
  // The environment as the kernels see it: the EXR's map, else the uniform radiance's 1x1 map.
  std::shared_ptr<const EnvironmentImage> environment_map() const {
    return environment_image ? environment_image : std::make_shared<const EnvironmentImage>(uniform_environment(environment));
  }
  bool has_environment() const {
    return environment_image || environment.x > 0.0f || environment.y > 0.0f || environment.z > 0.0f;
  }
  bool has_light() const { return emissive_triangles() > 0 || !lights.empty() || has_environment(); }
};

}  // namespace bp

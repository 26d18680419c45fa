#include "device/device_scene.h"
#include "device/launcher.h"
#include "scene/textures.h"

#include <cmath>

namespace bp {

std::vector<Material> pack_materials(const Scene& scene, const LightList& lights) {
  std::vector<Material> out;
  out.reserve(scene.materials.size());
  for (const SceneMaterial& m : scene.materials) {
    Material p{};
    for (int c = 0; c < 3; ++c) {
      p.kd[c] = m.kd[c];
      p.ks[c] = m.ks[c];
      p.emission[c] = m.emission[c];
    }
    p.shininess = m.shininess;
    p.light_pdf_area = lights.material_pdf_area.empty() ? 0.0f : lights.material_pdf_area[out.size()];
    p.flags = (m.double_sided ? BP_MATERIAL_DOUBLE_SIDED : 0u) | (m.ggx ? BP_MATERIAL_GGX : 0u);
    for (int c = 0; c < 3; ++c) {
      p.base_color[c] = m.base_color[c];
      p.dielectric_f0[c] = m.dielectric_f0[c];
    }
    p.metallic = m.metallic;
    p.roughness = m.roughness;
    p.specular_weight = m.specular_weight;
    if (m.transmission > 0.0f) {
      p.flags |= m.volume ? BP_MATERIAL_REFRACTOR : BP_MATERIAL_THIN_TRANSMITTER;
      for (int c = 0; c < 3; ++c) {
        p.transmission_tint[c] = m.transmission_tint[c] * m.transmission;
        p.attenuation[c] = m.volume ? m.attenuation[c] : 0.0f;
      }
      p.transmission = m.transmission;
    }
    p.ior = m.ior;
    out.push_back(p);
  }
  return out;
}

std::vector<TriangleShading> pack_triangle_shading(const Scene& scene, const PatchLayout& patches) {
  std::vector<TriangleShading> out(scene.triangles.size());
  std::uint32_t first_element = 0;
  const PatchClusters& clusters = patches.clusters;
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const SceneTriangle& t = scene.triangles[i];
    glm::vec3 c = glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
    float len = glm::length(c);
    glm::vec3 n = len > 0.0f ? c / len : glm::vec3(0.0f, 0.0f, 1.0f);
    TriangleShading& s = out[i];
    s = TriangleShading{};
    s.normal[0] = n.x; s.normal[1] = n.y; s.normal[2] = n.z;
    s.material = t.material;
    s.first_patch = patches.first_patch[i];
    s.patch_subdiv = patches.subdiv[i];
    s.area = 0.5f * len;
    s.first_element = first_element;  // the same numbering as build_bundle_geometry
    first_element += patches.subdiv[i] * patches.subdiv[i];
    if (!clusters.fans.empty()) {
      s.cluster_first_fan = clusters.fan_first[i];
      s.cluster_fans = clusters.fan_count[i];
    }
  }
  return out;
}

std::vector<ClusterFan> pack_cluster_fans(const Scene& scene, const PatchLayout& patches) {
  std::vector<ClusterFan> out(patches.clusters.fans.size());
  std::uint32_t first_element = 0;  // elements: the scene's triangles', then the fans' (build_bundle_geometry)
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) first_element += patches.subdiv[t] * patches.subdiv[t];
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::size_t t = scene.triangles.size() + i;
    const SceneTriangle& f = patches.clusters.fans[i];
    const glm::dvec3 e1(f.p[1] - f.p[0]), e2(f.p[2] - f.p[0]), n = glm::cross(e1, e2);
    // dual vectors in the plane: dual1 = (e2 x n) / ((e1 x e2) . n), dual2 = (n x e1) / ((e1 x e2) . n)
    const double det = glm::dot(n, n);
    const glm::dvec3 dual1 = glm::cross(e2, n) / det, dual2 = glm::cross(n, e1) / det;
    ClusterFan& c = out[i];
    for (int k = 0; k < 3; ++k) {
      c.p0[k] = f.p[0][k];
      c.dual1[k] = float(dual1[k]);
      c.dual2[k] = float(dual2[k]);
    }
    c.first_patch = patches.first_patch[t];
    c.patch_subdiv = patches.subdiv[t];
    c.first_element = first_element;
    first_element += patches.subdiv[t] * patches.subdiv[t];
  }
  return out;
}

std::vector<float> pack_shading_normals(const Scene& scene) {
  std::vector<float> out;
  if (!scene.has_shading_normals()) return out;
  out.reserve(9 * scene.triangles.size());
  for (const SceneTriangle& t : scene.triangles) {
    const glm::vec3 flat = glm::normalize(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = t.has_normals ? t.normal[k] : flat;
      out.insert(out.end(), {n.x, n.y, n.z});
    }
  }
  return out;
}

std::vector<float> pack_tangents(const Scene& scene) {
  std::vector<float> out;
  if (!scene.has_normal_maps()) return out;
  out.reserve(12 * scene.triangles.size());
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec4& c : t.tangent) out.insert(out.end(), {c.x, c.y, c.z, c.w});
  return out;
}

CameraParams pack_camera(const SceneCamera& camera, int width, int height) {
  CameraParams p{};
  glm::vec3 forward = glm::normalize(camera.forward);
  glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  glm::vec3 up = glm::cross(right, forward);
  float tan_y = std::tan(0.5f * camera.yfov);
  for (int c = 0; c < 3; ++c) {
    p.position[c] = camera.position[c];
    p.forward[c] = forward[c];
    p.right[c] = right[c];
    p.up[c] = up[c];
  }
  p.tan_half_fov_y = tan_y;
  p.tan_half_fov_x = tan_y * float(width) / float(height);  // square pixels: the image's aspect wins
  p.width = std::uint32_t(width);
  p.height = std::uint32_t(height);
  return p;
}

float ray_epsilon_for(const Bounds& bounds) {
  float diagonal = glm::length(bounds.extent());
  float magnitude = std::max(glm::length(bounds.lo), glm::length(bounds.hi));
  // 1e-5 of the scene, but never below a few float ulps of the coordinates themselves.
  return std::max(1e-5f * diagonal, 3e-7f * magnitude);
}

namespace {

template <typename T>
std::vector<T> at_least_one(std::vector<T> v) {
  if (v.empty()) v.emplace_back();  // OpenCL has no empty buffers
  return v;
}

}  // namespace

DeviceScene::DeviceScene(const DeviceContext& device, const Scene& scene, const PatchLayout& patches,
                         const FlatBvh& bvh, std::uint32_t selection) {
  LightList light_list = build_light_list(scene, bvh);
  for (const Light& l : light_list.lights)
    if (l.type == BP_LIGHT_POINT || l.type == BP_LIGHT_SPOT || l.type == BP_LIGHT_DIRECTIONAL)
      delta_light_share += l.select_probability;
  light_selection = selection;
  ray_epsilon = ray_epsilon_for(scene.bounds);
  std::vector<LightTreeNode> tree_in;
  std::vector<LightReceiver> receivers_in;
  if (selection == BP_LIGHT_SELECTION_TREE && !light_list.lights.empty()) {
    tree_in = build_light_tree(light_list, scene, ray_epsilon);  // also writes each light's trail
    receivers_in = build_light_receivers(scene, patches, light_list, ray_epsilon, &bvh);
  }
  tree_in = at_least_one(std::move(tree_in));
  receivers_in = at_least_one(std::move(receivers_in));
  const std::vector<TriangleShading> shading_in = pack_triangle_shading(scene, patches);
  const std::vector<ClusterFan> fans_in = at_least_one(pack_cluster_fans(scene, patches));
  const std::vector<Material> materials_in = pack_materials(scene, light_list);
  const std::vector<Light> lights_in = at_least_one(light_list.lights);
  const std::vector<float> cdf_in = at_least_one(light_list.cdf);
  std::vector<float> normals_in = pack_shading_normals(scene);
  has_shading_normals = normals_in.empty() ? 0u : 1u;
  const std::shared_ptr<const EnvironmentImage> environment_map = scene.environment_map();
  const std::vector<float> environment_in = at_least_one(pack_environment(*environment_map));
  environment_width = std::uint32_t(environment_map->width);
  environment_height = std::uint32_t(environment_map->height);
  environment_light = light_list.environment_light;
  environment = upload_buffer(device, "environment map", environment_in);
  environment_bytes = environment_map->empty() ? 0 : environment_in.size() * sizeof(float);
  normals_in = at_least_one(std::move(normals_in));
  const std::vector<float> tangents_in = at_least_one(pack_tangents(scene));
  const bool textured = scene.has_textures();
  uv_slots = textured ? scene.uv_slots : 0u;
  alpha_masks = scene.has_alpha_masks() ? 1u : 0u;
  const std::vector<TextureView> views_in = at_least_one(textured ? scene.texture_views : std::vector<TextureView>{});
  const std::vector<std::uint32_t> texels_in = at_least_one(textured ? scene.texels : std::vector<std::uint32_t>{});
  const std::vector<MaterialTextures> material_textures_in = at_least_one(pack_material_textures(scene));
  const std::vector<float> texcoords_in = at_least_one(pack_texcoords(scene));
  const std::vector<Material> patch_materials_in =
      at_least_one(textured ? patch_mean_materials(scene, patches, materials_in) : std::vector<Material>{});
  texture_views = upload_buffer(device, "texture views", views_in);
  texels = upload_buffer(device, "texels", texels_in);
  material_textures = upload_buffer(device, "material textures", material_textures_in);
  texcoords = upload_buffer(device, "texcoords", texcoords_in);
  patch_materials = upload_buffer(device, "patch mean materials", patch_materials_in);
  std::vector<std::uint32_t> element_triangle_in;
  std::vector<float> element_coverage_in;
  if (alpha_masks) {
    element_coverage_in = element_alpha_coverage(scene, patches);
    for (std::size_t t = 0; t < patch_triangle_count(scene, patches); ++t)
      element_triangle_in.insert(element_triangle_in.end(), std::size_t(patches.subdiv[t]) * patches.subdiv[t],
                                 std::uint32_t(scene_triangle_of(scene, patches, t)));
  }
  element_triangle_in = at_least_one(std::move(element_triangle_in));
  element_coverage_in = at_least_one(std::move(element_coverage_in));
  element_triangle = upload_buffer(device, "element triangles", element_triangle_in);
  element_coverage = upload_buffer(device, "element alpha coverage", element_coverage_in);
  // (the one-entry stand-ins of a scene without textures are not counted as texture memory)
  texture_bytes = !textured ? 0 : element_triangle_in.size() * sizeof(std::uint32_t) + element_coverage_in.size() * sizeof(float) +
                  views_in.size() * sizeof(TextureView) + texels_in.size() * sizeof(std::uint32_t) +
                  material_textures_in.size() * sizeof(MaterialTextures) + texcoords_in.size() * sizeof(float) +
                  patch_materials_in.size() * sizeof(Material);
  nodes = upload_buffer(device, "bvh nodes", bvh.nodes);
  triangles = upload_buffer(device, "bvh triangles", bvh.triangles);
  shading = upload_buffer(device, "triangle shading", shading_in);
  cluster_fans = upload_buffer(device, "cluster fans", fans_in);
  materials = upload_buffer(device, "materials", materials_in);
  lights = upload_buffer(device, "lights", lights_in);
  light_cdf = upload_buffer(device, "light cdf", cdf_in);
  light_tree = upload_buffer(device, "light tree", tree_in);
  light_receivers = upload_buffer(device, "light receivers", receivers_in);
  shading_normals = upload_buffer(device, "shading normals", normals_in);
  tangents = upload_buffer(device, "tangents", tangents_in);
  triangle_count = shading_in.size();
  node_count = bvh.nodes.size();
  light_count = std::uint32_t(light_list.lights.size());
  bytes = bvh.nodes.size() * sizeof(BvhNode) + bvh.triangles.size() * sizeof(BvhTriangle) +
          shading_in.size() * sizeof(TriangleShading) + fans_in.size() * sizeof(ClusterFan) + materials_in.size() * sizeof(Material) +
          lights_in.size() * sizeof(Light) + cdf_in.size() * sizeof(float) +
          tree_in.size() * sizeof(LightTreeNode) + receivers_in.size() * sizeof(LightReceiver) +
          (normals_in.size() + tangents_in.size()) * sizeof(float) + texture_bytes + environment_bytes;  // (textures' stand-ins: a few bytes, not counted)
}

}  // namespace bp

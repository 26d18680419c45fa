#include "scene/textures.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC  // private to this file (a test compiles its own copy)
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_image.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

namespace bp {

std::optional<DecodedImage> decode_image(const unsigned char* bytes, std::size_t size, std::string* error) {
  if (size == 0 || size > std::size_t(std::numeric_limits<int>::max())) {
    *error = size == 0 ? "is empty" : "is too large to decode";
    return std::nullopt;
  }
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(bytes, int(size), &w, &h, &channels)) {
    *error = std::string("is not a decodable PNG or JPEG (") + stbi_failure_reason() + ")";
    return std::nullopt;
  }
  if (w > kMaxTextureSide || h > kMaxTextureSide) {
    *error = "is " + std::to_string(w) + " x " + std::to_string(h) + " texels, beyond the limit of " +
             std::to_string(kMaxTextureSide) + " per side";
    return std::nullopt;
  }
  unsigned char* pixels = stbi_load_from_memory(bytes, int(size), &w, &h, &channels, 4);
  if (!pixels) {
    *error = std::string("is not a decodable PNG or JPEG (") + stbi_failure_reason() + ")";
    return std::nullopt;
  }
  DecodedImage out;
  out.width = w;
  out.height = h;
  out.rgba.resize(std::size_t(w) * h);
  for (std::size_t i = 0; i < out.rgba.size(); ++i) {
    const unsigned char* p = pixels + 4 * i;
    out.rgba[i] = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
  }
  stbi_image_free(pixels);
  return out;
}

std::optional<std::uint32_t> wrap_mode_from_gltf(int mode) {
  switch (mode) {
    case 10497: return BP_WRAP_REPEAT;
    case 33071: return BP_WRAP_CLAMP_TO_EDGE;
    case 33648: return BP_WRAP_MIRRORED_REPEAT;
    default: return std::nullopt;
  }
}

void texture_transform(float offset_u, float offset_v, float rotation, float scale_u, float scale_v, float out[6]) {
  // KHR_texture_transform: T R S with R = mat3(cos, sin, 0, -sin, cos, 0, 0, 0, 1) (column-major, as the spec's GLSL)
  const float c = std::cos(rotation), s = std::sin(rotation);
  out[0] = c * scale_u;   // column 0: R S e_u
  out[1] = s * scale_u;
  out[2] = -s * scale_v;  // column 1: R S e_v
  out[3] = c * scale_v;
  out[4] = offset_u;      // column 2: the offset
  out[5] = offset_v;
}

std::vector<float> pack_texcoords(const Scene& scene) {
  std::vector<float> out;
  if (!scene.has_textures() || scene.uv_slots == 0) return out;
  out.reserve(scene.triangles.size() * scene.uv_slots * 6);
  for (const SceneTriangle& t : scene.triangles)
    for (std::uint32_t s = 0; s < scene.uv_slots; ++s)
      for (int k = 0; k < 3; ++k) out.insert(out.end(), {t.uv[s][k].x, t.uv[s][k].y});
  return out;
}

std::vector<MaterialTextures> pack_material_textures(const Scene& scene) {
  std::vector<MaterialTextures> out;
  if (!scene.has_textures()) return out;
  for (const SceneMaterial& m : scene.materials) out.push_back(m.textures);
  return out;
}

TextureSet host_texture_set(const Scene& scene, const std::vector<MaterialTextures>& material_textures,
                            const std::vector<float>& texcoords) {
  TextureSet set{};
  set.views = scene.texture_views.data();
  set.texels = scene.texels.data();
  set.materials = material_textures.data();
  set.texcoords = texcoords.data();
  set.uv_slots = scene.uv_slots;
  return set;
}

namespace {

// Calls visit(b1, b2) at the centroids of the kPatchMeanSamplesPerSide^2 congruent sub-triangles of
// `sub`, in its triangle's barycentrics: the midpoint rule, exact for what is linear over the patch.
template <class Visit> void for_each_patch_point(const SubTriangle& sub, Visit&& visit) {
  constexpr std::uint32_t k = kPatchMeanSamplesPerSide;
  for (std::uint32_t p = 0; p < k * k; ++p) {
    float c1[3], c2[3];
    patch_corner_barycentrics(p, k, c1, c2);
    const float l1 = (c1[0] + c1[1] + c1[2]) / 3.0f, l2 = (c2[0] + c2[1] + c2[2]) / 3.0f, l0 = 1.0f - l1 - l2;
    visit(sub.b1[0] * l0 + sub.b1[1] * l1 + sub.b1[2] * l2, sub.b2[0] * l0 + sub.b2[1] * l1 + sub.b2[2] * l2);
  }
}

constexpr double kPatchPoints = double(kPatchMeanSamplesPerSide) * kPatchMeanSamplesPerSide;

}  // namespace

std::vector<Material> patch_mean_materials(const Scene& scene, const PatchLayout& patches,
                                           const std::vector<Material>& materials) {
  std::vector<Material> out(patches.patch_count);
  const std::vector<MaterialTextures> material_textures = pack_material_textures(scene);
  const std::vector<float> texcoords = pack_texcoords(scene);
  const TextureSet set = host_texture_set(scene, material_textures, texcoords);
  for_each_sub_triangle_in_parallel(scene, patches, [&](const SubTriangle& sub) {
    const SceneTriangle& tri = *sub.parent;  // (a cluster's fan is untextured: clusters.h)
    Material m = materials[tri.material];
    const SceneMaterial& sm = scene.materials[tri.material];
    if (sm.textured()) {
      double base[3] = {0, 0, 0}, le[3] = {0, 0, 0}, f0[3] = {0, 0, 0}, metallic = 0.0, roughness = 0.0;
      double specular = 0.0, points = 0.0;
      for_each_patch_point(sub, [&](float b1, float b2) {
        // alphaMode MASK: the mean over the part that is there (what RB's fragments are)
        if (!alpha_is_surface(&set, tri.material, std::uint32_t(sub.triangle), b1, b2)) return;
        points += 1.0;
        const TexelMaterial t = texel_material(&set, &sm.textures, std::uint32_t(sub.triangle), b1, b2);
        base[0] += t.base_color.x;
        base[1] += t.base_color.y;
        base[2] += t.base_color.z;
        le[0] += t.emission.x;
        le[1] += t.emission.y;
        le[2] += t.emission.z;
        metallic += t.metallic;
        roughness += t.roughness;
        specular += t.specular_weight;
        f0[0] += t.dielectric_f0.x;
        f0[1] += t.dielectric_f0.y;
        f0[2] += t.dielectric_f0.z;
      });
      if (points > 0.0) {
        for (int c = 0; c < 3; ++c) {
          m.base_color[c] = float(base[c] / points);
          m.emission[c] = float(le[c] / points);
        }
        m.metallic = float(metallic / points);
        m.roughness = float(roughness / points);
        if (sm.textures.specular != BP_NO_TEXTURE || sm.textures.specular_color != BP_NO_TEXTURE) {
          m.specular_weight = float(specular / points);
          for (int c = 0; c < 3; ++c) m.dielectric_f0[c] = float(f0[c] / points);
        }
        // a Lambert glTF material (metallic 0, no specular: the loader's choice) reflects kd = base colour
        if (!sm.ggx)
          for (int c = 0; c < 3; ++c) m.kd[c] = m.base_color[c] * (1.0f - m.metallic);
      }
    }
    const std::uint32_t front = patches.first_patch[sub.triangle] + sub.local;
    out[front] = m;
    if (sub.double_sided) out[front + sub.k2] = m;
  });
  return out;
}

std::vector<float> element_alpha_coverage(const Scene& scene, const PatchLayout& patches) {
  // elements: k^2 per patch triangle, in order
  std::vector<std::size_t> first_element(patch_triangle_count(scene, patches) + 1, 0);
  for (std::size_t t = 0; t + 1 < first_element.size(); ++t)
    first_element[t + 1] = first_element[t] + std::size_t(patches.subdiv[t]) * patches.subdiv[t];
  std::vector<float> out(first_element.back(), 1.0f);
  const std::vector<MaterialTextures> material_textures = pack_material_textures(scene);
  const std::vector<float> texcoords = pack_texcoords(scene);
  const TextureSet set = host_texture_set(scene, material_textures, texcoords);
  for_each_sub_triangle_in_parallel(scene, patches, [&](const SubTriangle& sub) {
    const std::uint32_t material = sub.parent->material;  // (a cluster's fan is never masked: clusters.h)
    if (!scene.materials[material].textured() || !(scene.materials[material].textures.alpha_cutoff > 0.0f)) return;
    double surface = 0.0;
    for_each_patch_point(sub, [&](float b1, float b2) {
      surface += alpha_is_surface(&set, material, std::uint32_t(sub.triangle), b1, b2);
    });
    out[first_element[sub.triangle] + sub.local] = float(surface / kPatchPoints);
  });
  return out;
}

}  // namespace bp

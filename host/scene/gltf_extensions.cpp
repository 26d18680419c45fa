// glTF extensions and ignored features (gltf_extensions.h). The rule: what the file asks for and
// the render leaves out gets a warning naming it; what the file requires and we cannot do, an error.
#include "scene/gltf_extensions.h"
#include "scene/tinygltf.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <string_view>
#include <utility>

namespace bp {
namespace {

using nlohmann::json;

// The extensions the loader reads (gltf_loader.cpp), or that cannot change the image. Both the
// extensionsRequired check and the warnings use this table, and nothing else.
constexpr std::string_view kSupported[] = {
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",      // factors and textures (texture.h's texel_material)
    "KHR_materials_transmission",  // a thin pane, or with a volume a refractor; what it cannot be is warned
    "KHR_materials_volume",        // thickness > 0: refracted, attenuated (gltf_loader.cpp's read_transmission)
    "KHR_mesh_quantization",       // integer vertex attributes (Loader::read_attribute)
    "KHR_texture_transform",
    "KHR_xmp_json_ld",  // metadata
};

// For extensions known and not supported: what the render does instead. Others get a generic line.
constexpr std::pair<std::string_view, std::string_view> kInstead[] = {
    {"KHR_materials_clearcoat", "the clearcoat layer is left out"},
    {"KHR_materials_sheen", "the sheen layer is left out"},
    {"KHR_materials_iridescence", "the thin-film iridescence is left out"},
    {"KHR_materials_anisotropy", "highlights are isotropic"},
    {"KHR_materials_dispersion", "one index of refraction serves every wavelength"},
    {"KHR_materials_diffuse_transmission", "no light diffuses through those surfaces"},
    {"KHR_materials_diffuse_roughness", "the diffuse base is Lambertian"},
    {"KHR_materials_unlit", "those materials are shaded as lit metallic-roughness materials"},
    {"KHR_materials_pbrSpecularGlossiness",
     "the materials' metallic-roughness values (glTF's defaults where absent) are rendered"},
    {"KHR_materials_variants", "each primitive keeps its default material"},
    {"KHR_texture_basisu", "KTX2 images are not decoded; those textures use their PNG or JPEG source, if any"},
    {"EXT_texture_webp", "WebP images are not decoded; those textures use their PNG or JPEG source, if any"},
    {"MSFT_texture_dds", "DDS images are not decoded; those textures use their PNG or JPEG source, if any"},
    {"KHR_draco_mesh_compression", "the primitives' uncompressed fallback attributes are read"},
    {"EXT_meshopt_compression", "the buffer views' uncompressed fallback data is read"},
    {"KHR_animation_pointer", "the properties it animates keep their static values"},
    {"EXT_mesh_gpu_instancing", "each node draws its mesh once, at its own transform; the instances are dropped"},
    {"EXT_lights_image_based", "the image-based light is left out (--environment gives one)"},
};

bool supported(std::string_view name) {
  return std::find(std::begin(kSupported), std::end(kSupported), name) != std::end(kSupported);
}

std::string supported_list() {
  std::string out;
  for (std::string_view name : kSupported) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

std::vector<std::string> string_array(const json& gltf, const char* key) {
  std::vector<std::string> out;
  if (auto it = gltf.find(key); it != gltf.end() && it->is_array())
    for (const json& v : *it)
      if (v.is_string()) out.push_back(v.get<std::string>());
  return out;
}

// Per extension name, the objects carrying it in their "extensions" (or in a sub-object's, as a
// material's textureInfo), by top-level array ("materials") and index; "" for the asset's own.
using Users = std::map<std::string, std::map<std::string, std::set<std::size_t>>>;

void collect_users(const json& top, const std::string& array, std::size_t index, Users& users) {
  std::vector<const json*> stack{&top};  // explicit: a file may nest deeper than the call stack
  while (!stack.empty()) {
    const json* j = stack.back();
    stack.pop_back();
    if (j->is_array())
      for (const json& v : *j) stack.push_back(&v);
    if (!j->is_object()) continue;
    for (const auto& [key, v] : j->items()) {
      if (key == "extras") continue;  // the application's own data, not glTF
      if (key == "extensions" && v.is_object())
        for (const auto& [name, unused] : v.items()) users[name][array].insert(index);
      stack.push_back(&v);
    }
  }
}

Users extension_users(const json& gltf) {
  Users users;
  for (const auto& [key, v] : gltf.items()) {
    if (key == "extensions") collect_users(json{{"extensions", v}}, "", 0, users);
    else if (key != "extras" && v.is_array())
      for (std::size_t i = 0; i < v.size(); ++i) collect_users(v[i], key, i, users);
  }
  return users;
}

// "bufferViews" -> "buffer views", the plural of an array's objects in words.
std::string plural(const std::string& array) {
  std::string out;
  for (char c : array) out += std::isupper((unsigned char)c) ? std::string(" ") + char(std::tolower(c)) : std::string(1, c);
  return out;
}

std::string singular(const std::string& array) {
  const std::string p = plural(array);
  return p.ends_with("shes") ? p.substr(0, p.size() - 2) : p.ends_with("s") ? p.substr(0, p.size() - 1) : p;
}

// "used by 3 materials and 1 texture", or where no object carries it, where it is named.
std::string usage(const std::map<std::string, std::set<std::size_t>>& by_array) {
  std::string out;
  for (const auto& [array, indices] : by_array) {
    if (array.empty()) continue;
    const std::size_t n = indices.size();
    out += (out.empty() ? "used by " : " and ") + std::to_string(n) + " " + (n == 1 ? singular(array) : plural(array));
  }
  if (!out.empty()) return out;
  return by_array.empty() ? "listed in extensionsUsed" : "in the asset's extensions";
}

std::string instead(const std::string& name) {
  for (const auto& [known, what] : kInstead)
    if (known == name) return std::string(what);
  return "it is ignored";
}

// KHR_draco_mesh_compression without a fallback: POSITION has no buffer view, so nothing to read.
std::string draco_without_fallback(const json& gltf) {
  const json empty = json::array();
  const json& meshes = gltf.contains("meshes") && gltf["meshes"].is_array() ? gltf["meshes"] : empty;
  const json& accessors = gltf.contains("accessors") && gltf["accessors"].is_array() ? gltf["accessors"] : empty;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const json* prims = meshes[m].is_object() && meshes[m].contains("primitives") ? &meshes[m]["primitives"] : nullptr;
    if (!prims || !prims->is_array()) continue;
    for (std::size_t p = 0; p < prims->size(); ++p) {
      const json& prim = (*prims)[p];
      if (!prim.is_object() || !prim.contains("extensions") || !prim["extensions"].is_object() ||
          !prim["extensions"].contains("KHR_draco_mesh_compression"))
        continue;
      const json position = prim.value("attributes", json::object()).value("POSITION", json());
      const std::size_t a = position.is_number_unsigned() ? position.get<std::size_t>() : accessors.size();
      const json& accessor = a < accessors.size() ? accessors[a] : empty;
      if (!accessor.is_object() || !(accessor.contains("bufferView") || accessor.contains("sparse")))
        return "mesh " + std::to_string(m) + " primitive " + std::to_string(p) +
               " is Draco-compressed (KHR_draco_mesh_compression) without uncompressed POSITION, and this "
               "renderer does not decode Draco";
    }
  }
  return "";
}

}  // namespace

// glTF 2.0 §3.12: a client that does not support an extension in extensionsRequired must not load
// the asset.
std::string gltf_extension_error(const json& gltf) {
  for (const std::string& name : string_array(gltf, "extensionsRequired"))
    if (!supported(name))
      return "requires " + name + " (extensionsRequired), which this renderer does not support (it supports " +
             supported_list() + ")";
  return draco_without_fallback(gltf);
}

std::vector<std::string> gltf_extension_warnings(const json& gltf) {
  Users users = extension_users(gltf);
  for (const std::string& name : string_array(gltf, "extensionsUsed")) users[name];  // listed, maybe on no object
  std::vector<std::string> out;
  for (const auto& [name, by_array] : users)
    if (!supported(name))
      out.push_back(name + " (" + usage(by_array) + ") is not supported; " + instead(name));
  return out;
}

std::vector<std::string> gltf_ignored_feature_warnings(const tinygltf::Model& model) {
  std::size_t occlusion = 0, coloured = 0, morphed = 0, skinned = 0, channels = 0;
  for (const auto& m : model.materials) occlusion += m.occlusionTexture.index >= 0;
  for (const auto& mesh : model.meshes) {
    bool targets = false;
    for (const auto& prim : mesh.primitives) {
      coloured += prim.attributes.count("COLOR_0") > 0;
      targets = targets || !prim.targets.empty();
    }
    morphed += targets;
  }
  for (const auto& node : model.nodes) skinned += node.skin >= 0;
  // Played: a camera node's translation and rotation (Loader::camera_animation, --camera-animation).
  for (const auto& animation : model.animations)
    for (const auto& channel : animation.channels) {
      const bool camera = channel.target_node >= 0 && std::size_t(channel.target_node) < model.nodes.size() &&
                          model.nodes[channel.target_node].camera >= 0;
      channels += !(camera && (channel.target_path == "translation" || channel.target_path == "rotation"));
    }
  std::vector<std::string> out;
  auto warn = [&](std::size_t n, const char* noun, const std::string& what) {
    if (n) out.push_back(what + " (" + std::to_string(n) + " " + noun + ")");
  };
  warn(occlusion, "material(s)", "occlusionTexture ignored: occlusion is computed by the renderer");
  warn(coloured, "primitive(s)", "COLOR_0 vertex colours ignored: the material's base colour is used");
  warn(morphed, "mesh(es)", "morph targets ignored: meshes keep their base shape, without the default weights");
  warn(skinned, "node(s)", "skins ignored: skinned meshes are drawn as stored, placed by their node");
  warn(channels, "channel(s)", "animations ignored: the scene is drawn at rest (only a camera's translation and "
                             "rotation are played, by --camera-animation)");
  return out;
}

}  // namespace bp

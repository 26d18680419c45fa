// glTF 2.0 -> Scene. tinygltf parses; every index and byte range is checked here, because
// tinygltf 2.7 trusts them. Every failure is one SceneError line "<path>: <object> <problem>".
#include "scene/gltf_loader.h"
#include "scene/camera_views.h"
#include "scene/gltf_extensions.h"
#include "scene/tangents.h"

#include "scene/textures.h"
#include "scene/tinygltf.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

namespace bp {
namespace {

constexpr int kModePoints = 0, kModeTriangles = 4, kModeStrip = 5, kModeFan = 6;
constexpr const char* kModeNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP",
                                      "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  std::string out;
  for (char c : s)  // collapse the runs the newline replacement leaves
    if (!(c == ' ' && !out.empty() && out.back() == ' ')) out += c;
  return out;
}

std::string quoted(const std::string& name) { return name.empty() ? "" : " \"" + name + "\""; }

std::string percent_decode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit((unsigned char)s[i + 1]) &&
        std::isxdigit((unsigned char)s[i + 2])) {
      out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// True if `uri` (not a data: URI) names a file inside the asset's folder: relative, no scheme,
// never climbing above its start with "..".
bool uri_stays_inside(const std::string& uri) {
  const std::string path = percent_decode(uri);
  if (path.empty() || path[0] == '/' || path[0] == '\\') return false;
  const auto slash = path.find_first_of("/\\");
  if (path.find(':') < slash) return false;  // "file:", "http:", "C:"
  int depth = 0;
  std::size_t start = 0;
  while (start <= path.size()) {
    std::size_t end = path.find_first_of("/\\", start);
    if (end == std::string::npos) end = path.size();
    const std::string part = path.substr(start, end - start);
    if (part == "..") {
      if (--depth < 0) return false;
    } else if (!part.empty() && part != ".") {
      ++depth;
    }
    start = end + 1;
  }
  return true;
}

std::uint32_t read_u32_le(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}

bool all_finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// tinygltf hands over the encoded bytes of data: URI and buffer-view images; keep them undecoded
// in image->image. The loader decodes only the images a material uses (Loader::image_texels).
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->width = image->height = 0;
  return true;
}

struct LocalTriangle {
  glm::vec3 p[3];
  std::uint32_t material;
  bool has_normals = false;
  glm::vec3 normal[3]{};  // NORMAL, local space
  glm::vec2 uv[BP_MAX_UV_SLOTS][3]{};  // TEXCOORD_n of the material's uv slots
  bool has_tangents = false;           // the material has a normal map: TANGENT (given or generated), local space
  glm::vec4 tangent[3]{};
};

class Loader {
 public:
  // `path` names the input in messages; `base_dir` is where relative buffer URIs resolve, or
  // nullopt for in-memory input, which refuses every buffer that is not a data: URI.
  Loader(std::string path, std::optional<std::string> base_dir)
      : path_(std::move(path)), base_dir_(std::move(base_dir)) {}

  Scene load(const std::vector<unsigned char>& bytes, bool binary) {
    parse(bytes, binary);
    scene_.source = path_;
    quantized_ = uses_extension("KHR_mesh_quantization");
    read_materials();
    traverse();
    for (std::string& w : gltf_ignored_feature_warnings(model_)) scene_.warnings.push_back(std::move(w));
    finish();
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw SceneError(one_line(path_ + ": " + what));
  }

  // ------------------------------------------------------------------ parsing

  void parse(const std::vector<unsigned char>& bytes, bool binary) {
    if (bytes.empty()) fail("file is empty, not glTF");
    if (bytes.size() > std::numeric_limits<unsigned>::max()) fail("file is too large (4 GiB or more)");
    const std::string base_dir = base_dir_.value_or("");

    tinygltf::TinyGLTF reader;
    reader.SetImageLoader(&keep_image_bytes, nullptr);
    std::string err, warn;
    bool ok = false;
    if (binary) {
      if (bytes.size() < 4 || std::memcmp(bytes.data(), "glTF", 4) != 0)
        fail("is not a binary .glb (no \"glTF\" magic)");
      precheck_json(glb_json_chunk(bytes), base_dir);
      ok = reader.LoadBinaryFromMemory(&model_, &err, &warn, bytes.data(),
                                       unsigned(bytes.size()), base_dir);
    } else {
      std::size_t first = 0;
      while (first < bytes.size() && std::isspace(bytes[first])) ++first;
      if (first == bytes.size() || bytes[first] != '{')
        fail("is not glTF (neither a JSON object nor a binary .glb)");
      precheck_json(std::string(bytes.begin(), bytes.end()), base_dir);
      ok = reader.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                      unsigned(bytes.size()), base_dir);
    }
    if (!ok) {
      std::string reason = err.empty() ? std::string("unknown error") : one_line(err);
      if (reason.size() > 300) reason = reason.substr(0, 300) + "...";  // tinygltf may quote a whole data: URI
      fail("glTF parse failed: " + reason);
    }
    std::istringstream lines(warn);
    for (std::string line; std::getline(lines, line);)
      if (!one_line(line).empty()) scene_.warnings.push_back("glTF: " + one_line(line));
  }

  // Extensions (scene/gltf_extensions.h): a required one we cannot do fails; an unsupported used one warns.
  void check_extensions(const nlohmann::json& j) {
    if (const std::string error = gltf_extension_error(j); !error.empty()) fail(error);
    for (std::string& w : gltf_extension_warnings(j)) scene_.warnings.push_back(std::move(w));
  }

  bool uses_extension(const std::string& name) const {
    const auto& used = model_.extensionsUsed;
    const auto& required = model_.extensionsRequired;
    return std::find(used.begin(), used.end(), name) != used.end() ||
           std::find(required.begin(), required.end(), name) != required.end();
  }

  // The JSON chunk of a .glb, after checking the header and chunk table.
  std::string glb_json_chunk(const std::vector<unsigned char>& b) const {
    if (b.size() < 20) fail(".glb header is truncated (" + std::to_string(b.size()) + " bytes)");
    const std::uint32_t version = read_u32_le(&b[4]), length = read_u32_le(&b[8]);
    if (version != 2) fail(".glb header has version " + std::to_string(version) + " (only 2 is supported)");
    if (length > b.size())
      fail(".glb header declares " + std::to_string(length) + " bytes but the file has " +
           std::to_string(b.size()));
    const std::uint32_t json_length = read_u32_le(&b[12]), json_type = read_u32_le(&b[16]);
    if (json_type != 0x4E4F534Au) fail(".glb first chunk is not JSON");
    if (std::uint64_t(json_length) + 20 > length) fail(".glb JSON chunk runs past the end of the file");
    std::uint64_t at = 20 + std::uint64_t(json_length);
    if (at + 8 <= length) {
      const std::uint32_t bin_length = read_u32_le(&b[at]);
      if (at + 8 + bin_length > length) fail(".glb BIN chunk runs past the end of the file");
    }
    return std::string(b.begin() + 20, b.begin() + 20 + json_length);
  }

  // Checks on the raw JSON that must happen before tinygltf reads it: a readable syntax error,
  // the extensions it requires, buffer URIs that stay in the asset's folder and exist, and the
  // indices tinygltf itself dereferences.
  void precheck_json(const std::string& text, const std::string& base_dir) {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // syntax errors, numbers out of range
      fail(std::string("invalid JSON: ") + e.what());
    }
    if (!j.is_object()) fail("is not glTF (the JSON top level is not an object)");
    check_extensions(j);
    auto array = [&](const char* key) -> const nlohmann::json& {
      static const nlohmann::json empty = nlohmann::json::array();
      auto it = j.find(key);
      return it != j.end() && it->is_array() ? *it : empty;
    };
    auto index = [](const nlohmann::json& o, const char* key) -> long long {
      auto it = o.find(key);
      return it != o.end() && it->is_number_integer() ? it->get<long long>() : -1;
    };
    const auto& buffers = array("buffers");
    for (std::size_t i = 0; i < buffers.size(); ++i) {
      if (!buffers[i].is_object() || !buffers[i].contains("uri") || !buffers[i]["uri"].is_string()) continue;
      const std::string uri = buffers[i]["uri"];
      if (uri.rfind("data:", 0) == 0) continue;
      if (!uri_stays_inside(uri))
        fail("buffer " + std::to_string(i) + " uri \"" + uri +
             "\" leaves the asset's folder (only relative paths inside it are allowed)");
      if (!base_dir_)
        fail("buffer " + std::to_string(i) + " uri \"" + uri +
             "\" is an external file, which in-memory input cannot refer to");
      std::error_code ec;
      if (!std::filesystem::is_regular_file(std::filesystem::path(base_dir) / percent_decode(uri), ec))
        fail("buffer " + std::to_string(i) + " uri \"" + uri + "\" names no file in " + base_dir);
    }
    const auto& accessors = array("accessors");
    const auto& views = array("bufferViews");
    const auto& meshes = array("meshes");
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      if (!meshes[m].is_object() || !meshes[m].contains("primitives")) continue;
      const auto& prims = meshes[m]["primitives"];
      if (!prims.is_array()) continue;
      for (std::size_t p = 0; p < prims.size(); ++p) {
        if (!prims[p].is_object() || !prims[p].contains("indices")) continue;
        const long long a = index(prims[p], "indices");
        const std::string role = "(indices of mesh " + std::to_string(m) + " primitive " + std::to_string(p) + ")";
        if (a < 0 || std::size_t(a) >= accessors.size())
          fail("accessor " + prims[p]["indices"].dump() + " " + role + " does not exist (the file has " +
               std::to_string(accessors.size()) + " accessors)");
        if (!accessors[a].is_object() || !accessors[a].contains("bufferView"))
          fail("accessor " + std::to_string(a) + " " + role + " has no buffer view");
        const long long v = index(accessors[a], "bufferView");
        if (v < 0 || std::size_t(v) >= views.size())
          fail("accessor " + std::to_string(a) + " " + role + " refers to buffer view " +
               accessors[a]["bufferView"].dump() + ", but the file has " + std::to_string(views.size()) +
               " buffer views");
      }
    }
    const auto& images = array("images");
    for (std::size_t i = 0; i < images.size(); ++i) {
      if (!images[i].is_object() || !images[i].contains("bufferView")) continue;
      const long long v = index(images[i], "bufferView");
      if (v < 0 || std::size_t(v) >= views.size() || !views[v].is_object())
        fail("image " + std::to_string(i) + " refers to a buffer view that does not exist");
      const long long b = index(views[v], "buffer");
      if (b < 0 || std::size_t(b) >= buffers.size() || !buffers[b].is_object())
        fail("buffer view " + std::to_string(v) + " refers to a buffer that does not exist");
      const auto num = [](const nlohmann::json& o, const char* key) -> double {
        auto it = o.find(key);
        return it != o.end() && it->is_number() ? it->get<double>() : 0.0;
      };
      if (num(views[v], "byteOffset") + num(views[v], "byteLength") > num(buffers[b], "byteLength"))
        fail("buffer view " + std::to_string(v) + " (image " + std::to_string(i) +
             ") runs past the end of buffer " + std::to_string(b));
    }
  }

  // ------------------------------------------------------------------ accessors

  std::string accessor_name(int index, const std::string& role) const {
    return "accessor " + std::to_string(index) + " (" + role + ")";
  }

  // The bytes of buffer view `v`, checked against its buffer.
  const unsigned char* view_bytes(int v, const std::string& user) const {
    if (v < 0 || std::size_t(v) >= model_.bufferViews.size())
      fail(user + " refers to buffer view " + std::to_string(v) + ", but the file has " +
           std::to_string(model_.bufferViews.size()) + " buffer views");
    const auto& view = model_.bufferViews[v];
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
      fail("buffer view " + std::to_string(v) + " refers to buffer " + std::to_string(view.buffer) +
           ", but the file has " + std::to_string(model_.buffers.size()) + " buffers");
    const auto& data = model_.buffers[view.buffer].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      fail("buffer view " + std::to_string(v) + " runs past the end of buffer " + std::to_string(view.buffer) +
           " (offset " + std::to_string(view.byteOffset) + " + length " + std::to_string(view.byteLength) +
           " > " + std::to_string(data.size()) + " bytes)");
    return data.data() + view.byteOffset;
  }

  // Checks that `count` elements of `element_size` bytes at `offset` with `stride` fit in `length`.
  static bool fits(std::uint64_t offset, std::uint64_t count, std::uint64_t stride,
                   std::uint64_t element_size, std::uint64_t length) {
    if (count == 0) return offset <= length;
    if (offset > length || element_size > length - offset) return false;
    return (count - 1) <= (length - offset - element_size) / stride;
  }

  static double component(const unsigned char* p, int type) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: { std::int8_t v; std::memcpy(&v, p, 1); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
      case TINYGLTF_COMPONENT_TYPE_SHORT: { std::int16_t v; std::memcpy(&v, p, 2); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
      default: { float v; std::memcpy(&v, p, 4); return v; }
    }
  }

  // Accessor `index` as count x components doubles, sparse substitutions applied. `role` names
  // its use for messages ("POSITION of mesh 0 primitive 1").
  std::vector<double> read_accessor(int index, const std::string& role, int want_type,
                                    const std::vector<int>& allowed_components) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
      fail(accessor_name(index, role) + " does not exist (the file has " +
           std::to_string(model_.accessors.size()) + " accessors)");
    const auto& acc = model_.accessors[index];
    const std::string name = accessor_name(index, role);
    if (acc.type != want_type)
      fail(name + " has type " + type_name(acc.type) + "; expected " + type_name(want_type));
    if (std::find(allowed_components.begin(), allowed_components.end(), acc.componentType) ==
        allowed_components.end())
      fail(name + " has unsupported component type " + std::to_string(acc.componentType) +
           (acc.normalized ? " (normalized integers)" : ""));
    const std::size_t ncomp = std::size_t(tinygltf::GetNumComponentsInType(acc.type));
    const std::size_t csize = std::size_t(tinygltf::GetComponentSizeInBytes(acc.componentType));
    const std::size_t esize = ncomp * csize;

    std::vector<double> out;
    if (acc.bufferView < 0 && !acc.sparse.isSparse) fail(name + " has no buffer view and is not sparse");
    if (acc.bufferView >= 0) {
      const unsigned char* base = view_bytes(acc.bufferView, name);
      const auto& view = model_.bufferViews[acc.bufferView];
      const std::size_t stride = view.byteStride ? view.byteStride : esize;
      if (stride < esize)
        fail("buffer view " + std::to_string(acc.bufferView) + " has byteStride " + std::to_string(stride) +
             ", smaller than an element of " + name + " (" + std::to_string(esize) + " bytes)");
      if (!fits(acc.byteOffset, acc.count, stride, esize, view.byteLength))
        fail(name + " runs past the end of buffer view " + std::to_string(acc.bufferView));
      out.resize(acc.count * ncomp);
      for (std::size_t i = 0; i < acc.count; ++i)
        for (std::size_t c = 0; c < ncomp; ++c)
          out[i * ncomp + c] = component(base + acc.byteOffset + i * stride + c * csize, acc.componentType);
    } else {  // a sparse accessor without a view starts from zeros
      // Nothing in the file bounds this count (a 300-byte file could ask for gigabytes of zeros), so
      // bound it here: 2^20 elements is far beyond any real view-less sparse POSITION or index accessor.
      if (acc.count > (std::size_t(1) << 20)) fail(name + " has an implausible count " + std::to_string(acc.count));
      out.assign(acc.count * ncomp, 0.0);
    }
    if (acc.sparse.isSparse) apply_sparse(acc, name, ncomp, csize, out);
    return out;
  }

  void apply_sparse(const tinygltf::Accessor& acc, const std::string& name, std::size_t ncomp,
                    std::size_t csize, std::vector<double>& out) const {
    const auto& sp = acc.sparse;
    if (sp.count < 1 || std::size_t(sp.count) > acc.count)
      fail(name + " has sparse count " + std::to_string(sp.count) + " outside [1, " +
           std::to_string(acc.count) + "]");
    const int itype = sp.indices.componentType;
    if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(name + " has sparse indices of unsupported component type " + std::to_string(itype));
    if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0)
      fail(name + " has a negative sparse byteOffset");
    const std::size_t isize = std::size_t(tinygltf::GetComponentSizeInBytes(itype));
    const unsigned char* ibase = view_bytes(sp.indices.bufferView, name + " sparse indices");
    if (!fits(std::size_t(sp.indices.byteOffset), std::size_t(sp.count), isize, isize,
              model_.bufferViews[sp.indices.bufferView].byteLength))
      fail(name + " sparse indices run past the end of buffer view " + std::to_string(sp.indices.bufferView));
    const unsigned char* vbase = view_bytes(sp.values.bufferView, name + " sparse values");
    const std::size_t esize = ncomp * csize;
    if (!fits(std::size_t(sp.values.byteOffset), std::size_t(sp.count), esize, esize,
              model_.bufferViews[sp.values.bufferView].byteLength))
      fail(name + " sparse values run past the end of buffer view " + std::to_string(sp.values.bufferView));
    double previous = -1.0;
    for (std::size_t s = 0; s < std::size_t(sp.count); ++s) {
      const double target = component(ibase + sp.indices.byteOffset + s * isize, itype);
      if (target >= double(acc.count))
        fail(name + " sparse index " + std::to_string(std::uint64_t(target)) + " is out of range (count " +
             std::to_string(acc.count) + ")");
      if (target <= previous)
        fail(name + " sparse indices are not strictly increasing at entry " + std::to_string(s));
      previous = target;
      for (std::size_t c = 0; c < ncomp; ++c)
        out[std::size_t(target) * ncomp + c] =
            component(vbase + sp.values.byteOffset + s * esize + c * csize, acc.componentType);
    }
  }

  // A vertex attribute: `core` component types, plus `quantized` ones where the file uses
  // KHR_mesh_quantization; normalized integers mapped to [0, 1] or [-1, 1] (glTF 3.11: signed c / (2^(n-1) - 1),
  // at least -1).
  std::vector<double> read_attribute(int index, const std::string& role, int type, std::vector<int> core,
                                     const std::vector<int>& quantized) const {
    if (quantized_) core.insert(core.end(), quantized.begin(), quantized.end());
    std::vector<double> out = read_accessor(index, role, type, core);
    const auto& acc = model_.accessors[index];
    if (!acc.normalized || acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) return out;
    const double max = acc.componentType == TINYGLTF_COMPONENT_TYPE_BYTE            ? 127.0
                       : acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 255.0
                       : acc.componentType == TINYGLTF_COMPONENT_TYPE_SHORT         ? 32767.0
                                                                                    : 65535.0;
    for (double& v : out) v = std::max(v / max, -1.0);
    return out;
  }

  static std::string type_name(int type) {
    switch (type) {
      case TINYGLTF_TYPE_SCALAR: return "SCALAR";
      case TINYGLTF_TYPE_VEC2: return "VEC2";
      case TINYGLTF_TYPE_VEC3: return "VEC3";
      case TINYGLTF_TYPE_VEC4: return "VEC4";
      case TINYGLTF_TYPE_MAT2: return "MAT2";
      case TINYGLTF_TYPE_MAT3: return "MAT3";
      case TINYGLTF_TYPE_MAT4: return "MAT4";
      default: return std::to_string(type);
    }
  }

  // ------------------------------------------------------------------ materials

  glm::vec3 rgb(const tinygltf::Value& v, const std::string& where) const {
    if (!v.IsArray() || v.ArrayLen() != 3) fail(where + " is not an array of 3 numbers");
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) {
      if (!v.Get(i).IsNumber()) fail(where + " is not an array of 3 numbers");
      out[i] = float(v.Get(i).GetNumberAsDouble());
    }
    return out;
  }

  static const tinygltf::Value* member(const tinygltf::Value& v, const char* key) {
    return v.IsObject() && v.Has(key) ? &v.Get(key) : nullptr;
  }
  static const tinygltf::Value* extension(const tinygltf::ExtensionMap& ext, const char* name, const char* key) {
    auto it = ext.find(name);
    return it == ext.end() ? nullptr : member(it->second, key);
  }

  // ------------------------------------------------------------------ textures

  // The encoded bytes of image `i`: its buffer view, data: URI (both kept by keep_image_bytes), or
  // the file its uri names beside the asset (the buffers' folder rule).
  std::vector<unsigned char> image_bytes(int i, const std::string& obj) const {
    const auto& image = model_.images[i];
    if (image.bufferView >= 0) {
      const unsigned char* p = view_bytes(image.bufferView, obj);
      return std::vector<unsigned char>(p, p + model_.bufferViews[image.bufferView].byteLength);
    }
    if (!image.image.empty() || image.uri.empty()) return image.image;
    if (!uri_stays_inside(image.uri))
      fail(obj + " uri \"" + image.uri + "\" leaves the asset's folder (only relative paths inside it are allowed)");
    if (!base_dir_) fail(obj + " uri \"" + image.uri + "\" is an external file, which in-memory input cannot refer to");
    const std::filesystem::path file = std::filesystem::path(*base_dir_) / percent_decode(image.uri);
    std::ifstream in(file, std::ios::binary);
    if (!in) fail(obj + " uri \"" + image.uri + "\" names no readable file in " + *base_dir_);
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) fail(obj + " uri \"" + image.uri + "\": read error");
    return bytes;
  }

  struct ImageTexels {
    std::uint32_t first = 0, width = 0, height = 0;
  };

  // Image `i` decoded into the scene's texel buffer, once however many textures use it.
  ImageTexels image_texels(int i, const std::string& user) {
    if (i < 0 || std::size_t(i) >= model_.images.size())
      fail(user + " refers to image " + std::to_string(i) + ", but the file has " +
           std::to_string(model_.images.size()) + " images");
    if (auto found = decoded_images_.find(i); found != decoded_images_.end()) return found->second;
    const auto& image = model_.images[i];
    std::string obj = "image " + std::to_string(i) + quoted(image.name);
    if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0) obj += " (\"" + image.uri + "\")";
    const std::vector<unsigned char> bytes = image_bytes(i, obj);
    std::string error;
    const auto decoded = decode_image(bytes.data(), bytes.size(), &error);
    if (!decoded) fail(obj + " " + error);
    const std::uint64_t total = std::uint64_t(scene_.texels.size()) + decoded->rgba.size();
    if (total > kMaxSceneTexels)
      fail(obj + " brings the scene's textures to " + std::to_string(total) + " texels, beyond the limit of " +
           std::to_string(kMaxSceneTexels));
    ImageTexels t{std::uint32_t(scene_.texels.size()), std::uint32_t(decoded->width), std::uint32_t(decoded->height)};
    scene_.texels.insert(scene_.texels.end(), decoded->rgba.begin(), decoded->rgba.end());
    return decoded_images_.emplace(i, t).first->second;
  }

  static const tinygltf::Value* number_pair(const tinygltf::Value* v) {
    return v && v->IsArray() && v->ArrayLen() == 2 && v->Get(0).IsNumber() && v->Get(1).IsNumber() ? v : nullptr;
  }

  // The view of textureInfo `info` (used as `slot_name` of material `mat`), its texcoord set added
  // to the material's uv sets; BP_NO_TEXTURE when there is no texture or its image is in a format
  // we cannot read (a warning).
  std::uint32_t texture_view(const tinygltf::TextureInfo& info, const std::string& obj, bool srgb,
                             std::vector<int>& uv_sets) {
    if (info.index == -1) return BP_NO_TEXTURE;
    if (info.index < 0 || std::size_t(info.index) >= model_.textures.size())
      fail(obj + " refers to texture " + std::to_string(info.index) + ", but the file has " +
           std::to_string(model_.textures.size()) + " textures");
    const auto& texture = model_.textures[info.index];
    const std::string tex_obj = obj + " (texture " + std::to_string(info.index) + ")";
    if (texture.source == -1) {
      scene_.warnings.push_back(tex_obj + " has no PNG or JPEG source; ignored");
      return BP_NO_TEXTURE;
    }
    const ImageTexels image = image_texels(texture.source, tex_obj);
    TextureView view{};
    view.first_texel = image.first;
    view.width = image.width;
    view.height = image.height;
    std::uint32_t wrap_s = BP_WRAP_REPEAT, wrap_t = BP_WRAP_REPEAT;
    if (texture.sampler != -1) {
      if (texture.sampler < 0 || std::size_t(texture.sampler) >= model_.samplers.size())
        fail(tex_obj + " refers to sampler " + std::to_string(texture.sampler) + ", but the file has " +
             std::to_string(model_.samplers.size()) + " samplers");
      const auto& sampler = model_.samplers[texture.sampler];
      const auto s = wrap_mode_from_gltf(sampler.wrapS), t = wrap_mode_from_gltf(sampler.wrapT);
      if (!s || !t)
        fail("sampler " + std::to_string(texture.sampler) + " has wrap modes " + std::to_string(sampler.wrapS) +
             ", " + std::to_string(sampler.wrapT) + " (glTF allows 10497, 33071, 33648)");
      wrap_s = *s;
      wrap_t = *t;
      if (sampler.magFilter == 9728) view.flags |= BP_TEXTURE_NEAREST;  // NEAREST
    }
    view.flags |= wrap_s | wrap_t << BP_TEXTURE_WRAP_T_SHIFT | (srgb ? BP_TEXTURE_SRGB : 0u);
    int set = info.texCoord;
    texture_transform(0.0f, 0.0f, 0.0f, 1.0f, 1.0f, view.transform);
    if (auto ext = info.extensions.find("KHR_texture_transform"); ext != info.extensions.end()) {
      const tinygltf::Value& x = ext->second;
      const std::string where = obj + " KHR_texture_transform";
      const auto* offset = member(x, "offset");
      const auto* scale = member(x, "scale");
      const auto* rotation = member(x, "rotation");
      const auto* tc = member(x, "texCoord");
      if ((offset && !number_pair(offset)) || (scale && !number_pair(scale)) || (rotation && !rotation->IsNumber()) ||
          (tc && !tc->IsInt()))
        fail(where + " is malformed (offset and scale: 2 numbers, rotation: a number, texCoord: an integer)");
      auto num = [](const tinygltf::Value* v, int i, double fallback) {
        return v ? (i < 0 ? v->GetNumberAsDouble() : v->Get(i).GetNumberAsDouble()) : fallback;
      };
      texture_transform(float(num(offset, 0, 0.0)), float(num(offset, 1, 0.0)), float(num(rotation, -1, 0.0)),
                        float(num(scale, 0, 1.0)), float(num(scale, 1, 1.0)), view.transform);
      for (float f : view.transform)
        if (!std::isfinite(f)) fail(where + " is not finite");
      if (tc) set = tc->GetNumberAsInt();
    }
    if (set < 0) fail(obj + " has texCoord " + std::to_string(set));
    auto slot = std::find(uv_sets.begin(), uv_sets.end(), set);
    if (slot == uv_sets.end()) {
      if (uv_sets.size() == BP_MAX_UV_SLOTS)
        fail(obj + " reads TEXCOORD_" + std::to_string(set) + ", but its material already reads " +
             std::to_string(BP_MAX_UV_SLOTS) + " texcoord sets (the most supported)");
      uv_sets.push_back(set);
      slot = uv_sets.end() - 1;
    }
    view.uv_slot = std::uint32_t(slot - uv_sets.begin());
    scene_.texture_views.push_back(view);
    return std::uint32_t(scene_.texture_views.size() - 1);
  }

  // Core glTF's textures of material `m` into out.textures, with the factors they multiply.
  void read_textures(const tinygltf::Material& m, const std::string& obj, SceneMaterial& out) {
    const auto& pbr = m.pbrMetallicRoughness;
    MaterialTextures& t = out.textures;
    std::vector<int> uv_sets;
    t.base_color = texture_view(pbr.baseColorTexture, obj + " baseColorTexture", true, uv_sets);
    t.metallic_roughness = texture_view(pbr.metallicRoughnessTexture, obj + " metallicRoughnessTexture", false, uv_sets);
    t.emissive = texture_view(m.emissiveTexture, obj + " emissiveTexture", true, uv_sets);
    read_normal_texture(m.normalTexture, obj + " normalTexture", t, uv_sets);
    // KHR_materials_specular's textures (its factors: read_metallic_roughness)
    const std::string specular = obj + " KHR_materials_specular";
    t.specular = texture_view(extension_texture(m, "KHR_materials_specular", "specularTexture", specular),
                              specular + ".specularTexture", false, uv_sets);
    t.specular_color = texture_view(extension_texture(m, "KHR_materials_specular", "specularColorTexture", specular),
                                    specular + ".specularColorTexture", true, uv_sets);
    for (int c = 0; c < 3; ++c) {
      t.base_color_factor[c] = out.base_color[c];
      t.emissive_factor[c] = out.emission[c];
    }
    t.base_color_factor[3] = pbr.baseColorFactor.size() == 4 ? float(pbr.baseColorFactor[3]) : 1.0f;
    t.metallic_factor = out.metallic;
    t.roughness_factor = out.roughness;
    // alphaMode MASK (docs/design.md §6): where alpha (factor x texel) is below the cutoff there is no surface
    bool cut_away = false;
    if (m.alphaMode == "MASK") {
      const double cutoff = m.alphaCutoff;
      if (!(cutoff >= 0.0 && std::isfinite(cutoff))) fail(obj + " has alphaCutoff " + std::to_string(cutoff));
      if (t.base_color != BP_NO_TEXTURE)
        t.alpha_cutoff = float(cutoff);
      else
        cut_away = t.base_color_factor[3] < cutoff;  // the same alpha everywhere: all surface or none
    } else if (m.alphaMode == "BLEND") {
      scene_.warnings.push_back(obj + " has alphaMode BLEND; rendered opaque");
    }
    material_cut_away_.push_back(cut_away);
    material_uv_sets_.push_back(out.textured() || out.has_normal_map() ? uv_sets : std::vector<int>{});
    scene_.uv_slots = std::max(scene_.uv_slots, std::uint32_t(material_uv_sets_.back().size()));
  }

  // A textureInfo inside extension `name` of material m as `key` (index -1 where absent).
  tinygltf::TextureInfo extension_texture(const tinygltf::Material& m, const char* name, const char* key,
                                          const std::string& obj) const {
    tinygltf::TextureInfo info;
    const tinygltf::Value* v = extension(m.extensions, name, key);
    if (!v) return info;
    const tinygltf::Value* index = member(*v, "index");
    const tinygltf::Value* tc = member(*v, "texCoord");
    if (!index || !index->IsInt() || (tc && !tc->IsInt()))
      fail(obj + "." + key + " is malformed (index: an integer, texCoord: an integer)");
    info.index = index->GetNumberAsInt();
    if (info.index < 0) fail(obj + "." + key + " has index " + std::to_string(info.index));
    info.texCoord = tc ? tc->GetNumberAsInt() : 0;
    if (const tinygltf::Value* ext = member(*v, "extensions"); ext && ext->IsObject())
      for (const std::string& k : ext->Keys()) info.extensions[k] = ext->Get(k);
    return info;
  }

  // normalTexture (docs/design.md §6): a linear RGB view like the others, and its scale.
  void read_normal_texture(const tinygltf::NormalTextureInfo& normal, const std::string& obj, MaterialTextures& t,
                           std::vector<int>& uv_sets) {
    tinygltf::TextureInfo info;
    info.index = normal.index;
    info.texCoord = normal.texCoord;
    info.extensions = normal.extensions;
    t.normal = texture_view(info, obj, false, uv_sets);
    if (!std::isfinite(normal.scale)) fail(obj + " scale is not finite");
    t.normal_scale = float(normal.scale);
  }

  // A factor that glTF bounds to [lo, hi]; anything else (negative, NaN, infinite, too large) is an
  // error that names the material and the field.
  float bounded_factor(double v, double lo, double hi, const std::string& where) const {
    if (!(v >= lo && v <= hi)) {
      std::ostringstream e;
      e << where << " is " << v << "; glTF allows [" << lo << ", " << hi << "]";
      fail(e.str());
    }
    return float(v);
  }

  // glTF's metallic-roughness material as its specification's Appendix B writes it (docs/design.md §11),
  // with KHR_materials_ior and KHR_materials_specular (kernels/shared/metallic_roughness.h). Where it
  // is exactly Lambert (metallic 0 and specular 0: no Fresnel layer at all) it stays the Lambert
  // material kd = baseColor, which RB gathers in blocks.
  void read_metallic_roughness(const tinygltf::Material& m, const std::string& obj, SceneMaterial& out) {
    const auto& pbr = m.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4) fail(obj + " baseColorFactor is not an array of 4 numbers");
    for (int c = 0; c < 3; ++c) out.base_color[c] = bounded_factor(pbr.baseColorFactor[c], 0.0, 1.0, obj + " baseColorFactor");
    bounded_factor(pbr.baseColorFactor[3], 0.0, 1.0, obj + " baseColorFactor");
    out.metallic = bounded_factor(pbr.metallicFactor, 0.0, 1.0, obj + " metallicFactor");
    out.roughness = bounded_factor(pbr.roughnessFactor, 0.0, 1.0, obj + " roughnessFactor");
    // KHR_materials_ior: ior 1.5 by default; 0 or at least 1, 0 meaning f0 = 1 (its specification)
    double ior = 1.5;
    if (const auto* v = extension(m.extensions, "KHR_materials_ior", "ior")) {
      if (!v->IsNumber()) fail(obj + " KHR_materials_ior.ior is not a number");
      ior = v->GetNumberAsDouble();
      if (!(ior == 0.0 || (ior >= 1.0 && std::isfinite(ior)))) {
        std::ostringstream e;
        e << obj << " KHR_materials_ior.ior is " << ior << "; it must be 0 or at least 1";
        fail(e.str());
      }
    }
    // f0 = ((ior - outside_ior) / (ior + outside_ior))^2 with air outside (KHR_materials_ior); ior 0: 1
    const float f0_ior = ior == 0.0 ? 1.0f : float(((ior - 1.0) / (ior + 1.0)) * ((ior - 1.0) / (ior + 1.0)));
    // KHR_materials_specular: specular in [0, 1], specularColor >= 0 (it may pass 1)
    out.specular_weight = 1.0f;
    if (const auto* v = extension(m.extensions, "KHR_materials_specular", "specularFactor")) {
      if (!v->IsNumber()) fail(obj + " KHR_materials_specular.specularFactor is not a number");
      out.specular_weight = bounded_factor(v->GetNumberAsDouble(), 0.0, 1.0, obj + " KHR_materials_specular.specularFactor");
    }
    glm::vec3 specular_colour(1.0f);
    if (const auto* v = extension(m.extensions, "KHR_materials_specular", "specularColorFactor")) {
      const std::string where = obj + " KHR_materials_specular.specularColorFactor";
      specular_colour = rgb(*v, where);
      for (int c = 0; c < 3; ++c)
        bounded_factor(specular_colour[c], 0.0, std::numeric_limits<float>::max(), where);
    }
    // dielectric_f0 = min(f0(ior) specularColor, 1), times specular in the Fresnel term (KHR_materials_specular)
    out.dielectric_f0 = glm::min(f0_ior * specular_colour, glm::vec3(1.0f));
    out.textures.specular_factor = out.specular_weight;  // what the textures multiply (texel_material)
    for (int c = 0; c < 3; ++c) out.textures.specular_f0[c] = f0_ior * specular_colour[c];
    out.ggx = !(out.metallic == 0.0f && out.specular_weight == 0.0f);
    out.kd = out.ggx ? glm::vec3(0.0f) : out.base_color;
    out.ks = glm::vec3(0.0f);
  }

  void read_materials() {
    SceneMaterial fallback;
    fallback.name = "default";  // kd 0.8 grey Lambert, for primitives without a material
    scene_.materials.push_back(fallback);
    material_uv_sets_.emplace_back();
    material_cut_away_.push_back(false);
    for (std::size_t i = 0; i < model_.materials.size(); ++i) {
      const auto& m = model_.materials[i];
      const std::string obj = "material " + std::to_string(i) + quoted(m.name);
      SceneMaterial out;
      out.name = m.name.empty() ? "material " + std::to_string(i) : m.name;
      out.double_sided = m.doubleSided;
      bool pbr_material = false;
      if (const auto* phong = member(m.extras, "phong")) {
        const auto* kd = member(*phong, "kd");
        const auto* ks = member(*phong, "ks");
        const auto* n = member(*phong, "shininess");
        out.kd = kd ? rgb(*kd, obj + " extras.phong.kd") : glm::vec3(0.0f);
        out.ks = ks ? rgb(*ks, obj + " extras.phong.ks") : glm::vec3(0.0f);
        if (n && !n->IsNumber()) fail(obj + " extras.phong.shininess is not a number");
        out.shininess = n ? float(n->GetNumberAsDouble()) : 1.0f;
      } else {
        read_metallic_roughness(m, obj, out);
        pbr_material = true;
      }
      float strength = 1.0f;
      if (const auto* s = extension(m.extensions, "KHR_materials_emissive_strength", "emissiveStrength")) {
        if (!s->IsNumber()) fail(obj + " KHR_materials_emissive_strength.emissiveStrength is not a number");
        strength = float(s->GetNumberAsDouble());
      }
      if (m.emissiveFactor.size() == 3)
        out.emission = strength * glm::vec3(float(m.emissiveFactor[0]), float(m.emissiveFactor[1]),
                                            float(m.emissiveFactor[2]));
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(out.kd[c]) || !std::isfinite(out.ks[c]) || out.kd[c] < 0.0f || out.ks[c] < 0.0f)
          fail(obj + " has a negative or non-finite kd/ks");
        if (!std::isfinite(out.emission[c]) || out.emission[c] < 0.0f)
          fail(obj + " has a negative or non-finite emission");
      }
      if (!std::isfinite(out.shininess) || out.shininess < 0.0f)
        fail(obj + " has a negative or non-finite shininess");
      if (pbr_material) {
        read_textures(m, obj, out);
      } else {
        material_uv_sets_.emplace_back();
        material_cut_away_.push_back(false);
        if (m.pbrMetallicRoughness.baseColorTexture.index >= 0 || m.emissiveTexture.index >= 0 ||
            m.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0 || m.normalTexture.index >= 0 ||
            extension(m.extensions, "KHR_materials_specular", "specularTexture") ||
            extension(m.extensions, "KHR_materials_specular", "specularColorTexture"))
          scene_.warnings.push_back(obj + ": extras.phong wins; its textures are ignored");
      }
      const float max_albedo = bp_max(out.kd + out.ks);
      if (max_albedo > 1.0f) {  // docs/design.md §6: max(kd + ks) <= 1 (Modified Phong's; glTF's model keeps energy)
        out.kd /= max_albedo;
        out.ks /= max_albedo;
        std::ostringstream w;
        w << obj << ": kd + ks reaches " << max_albedo << " > 1; kd and ks scaled down to keep energy";
        scene_.warnings.push_back(w.str());
      }
      read_transmission(m, obj, out);
      scene_.materials.push_back(out);
    }
  }

  // A number of an extension, `fallback` where absent; fail(obj ...) where it is not a number.
  double extension_number(const tinygltf::Material& m, const std::string& obj, const char* name, const char* key,
                          double fallback) const {
    const auto* v = extension(m.extensions, name, key);
    if (!v) return fallback;
    if (!v->IsNumber()) fail(obj + " " + name + "." + key + " is not a number");
    return v->GetNumberAsDouble();
  }

  // KHR_materials_transmission with KHR_materials_ior, thin-walled (docs/design.md §11): the share
  // T (1 - metallic) of the surface becomes a pane (kernels/shared/thin_glass.h) and the rest of it
  // the opaque BSDF, scaled by 1 - that share. What the pane cannot be -- a volume, a textured T or colour, a
  // rough pane, an emitting one -- is said per material.
  void read_transmission(const tinygltf::Material& m, const std::string& obj, SceneMaterial& out) {
    const bool has_volume = m.extensions.count("KHR_materials_volume") > 0;
    if (!m.extensions.count("KHR_materials_transmission")) {
      if (has_volume) scene_.warnings.push_back(obj + ": KHR_materials_volume without KHR_materials_transmission; ignored");
      return;
    }
    const double factor = extension_number(m, obj, "KHR_materials_transmission", "transmissionFactor", 0.0);
    if (!(factor >= 0.0 && factor <= 1.0))
      fail(obj + " KHR_materials_transmission.transmissionFactor is " + std::to_string(factor) + " (must be in [0, 1])");
    const double ior = extension_number(m, obj, "KHR_materials_ior", "ior", 1.5);
    if (!(ior == 0.0 || (ior >= 1.0 && std::isfinite(ior))))
      fail(obj + " KHR_materials_ior.ior is " + std::to_string(ior) + " (must be 0 or at least 1)");
    const double thickness = extension_number(m, obj, "KHR_materials_volume", "thicknessFactor", 0.0);
    if (!(thickness >= 0.0 && std::isfinite(thickness)))
      fail(obj + " KHR_materials_volume.thicknessFactor is " + std::to_string(thickness) + " (must be >= 0)");
    if (extension(m.extensions, "KHR_materials_transmission", "transmissionTexture"))
      scene_.warnings.push_back(obj + ": KHR_materials_transmission.transmissionTexture ignored; transmissionFactor " +
                                std::to_string(factor) + " used everywhere");
    const auto& pbr = m.pbrMetallicRoughness;
    const double metallic = member(m.extras, "phong") ? 0.0 : pbr.metallicFactor;  // metal does not transmit
    const float share = float(factor * (1.0 - metallic));
    if (!(share > 0.0f)) return;
    if (out.emission.x > 0.0f || out.emission.y > 0.0f || out.emission.z > 0.0f) {
      scene_.warnings.push_back(obj + " emits: KHR_materials_transmission ignored (an emitter is opaque)");
      return;
    }
    out.volume = has_volume && thickness > 0.0;
    if (out.volume) read_volume_attenuation(m, obj, out);
    if (pbr.roughnessFactor > 0.0)
      scene_.warnings.push_back(obj + ": roughness " + std::to_string(pbr.roughnessFactor) + " of a transmitter; " +
                                (out.volume ? "it refracts and reflects as smooth glass"
                                            : "its pane passes light straight through and mirrors the rest"));
    if (pbr.baseColorTexture.index >= 0)
      scene_.warnings.push_back(obj + ": the pane's colour is baseColorFactor; baseColorTexture tints only the opaque rest");
    if (m.extensions.count("KHR_materials_specular"))
      scene_.warnings.push_back(obj + ": the pane's Fresnel reflection ignores KHR_materials_specular");
    if (pbr.baseColorFactor.size() >= 3)
      out.transmission_tint = glm::vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                                        float(pbr.baseColorFactor[2]));
    out.transmission = share;
    out.ior = float(ior);
    // the opaque rest: 1 - share of the BSDF. Phong's (and Lambert's) kd and ks here, its texels too (the
    // colour factor they multiply); a GGX material's f is scaled in the kernels (metallic_roughness.h),
    // since no one factor of its model scales the whole of it.
    if (out.ggx) return;
    const float rest = 1.0f - share;
    out.kd *= rest;
    out.ks *= rest;
    for (int c = 0; c < 3; ++c) out.textures.base_color_factor[c] *= rest;
  }

  // KHR_materials_volume's medium: attenuationColor reached after attenuationDistance (world metres;
  // absent: no attenuation), as the coefficient -ln(colour) / distance, m^-1. A black channel
  // absorbs everything that enters (a large finite coefficient, not infinity: exp(-inf 0) is NaN).
  void read_volume_attenuation(const tinygltf::Material& m, const std::string& obj, SceneMaterial& out) {
    const double distance = extension_number(m, obj, "KHR_materials_volume", "attenuationDistance",
                                             std::numeric_limits<double>::infinity());
    if (!(distance > 0.0))
      fail(obj + " KHR_materials_volume.attenuationDistance is " + std::to_string(distance) + " (must be > 0)");
    glm::vec3 colour(1.0f);
    if (const auto* v = extension(m.extensions, "KHR_materials_volume", "attenuationColor")) {
      const std::string where = obj + " KHR_materials_volume.attenuationColor";
      colour = rgb(*v, where);
      for (int c = 0; c < 3; ++c) bounded_factor(colour[c], 0.0, 1.0, where);
    }
    for (int c = 0; c < 3; ++c)
      out.attenuation[c] = !std::isfinite(distance) || colour[c] >= 1.0f ? 0.0f
                           : colour[c] > 0.0f                            ? float(-std::log(double(colour[c])) / distance)
                                                                         : 1e30f;
    // thicknessFactor and thicknessTexture stand in for the geometry a rasteriser does not trace; the
    // mesh itself is refracted here, so they only say that the medium exists.
  }

  static float bp_max(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

  // ------------------------------------------------------------------ meshes

  std::vector<std::uint32_t> read_indices(int index, const std::string& role) const {
    const auto raw = read_accessor(index, role, TINYGLTF_TYPE_SCALAR,
                                   {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
    return std::vector<std::uint32_t>(raw.begin(), raw.end());
  }

  // TEXCOORD_n of a primitive for each of its material's uv sets (glTF: VEC2 of float, or of
  // normalized unsigned byte or short), one per POSITION; a set the primitive lacks reads (0, 0).
  std::vector<std::vector<glm::vec2>> read_texcoords(const tinygltf::Primitive& prim, const std::string& obj,
                                                     const std::vector<int>& sets, std::size_t vertices) {
    std::vector<std::vector<glm::vec2>> out;
    for (int set : sets) {
      const std::string name = "TEXCOORD_" + std::to_string(set);
      auto it = prim.attributes.find(name);
      if (it == prim.attributes.end()) {
        ++missing_texcoords_;
        out.emplace_back(vertices, glm::vec2(0.0f));
        continue;
      }
      const std::string role = name + " of " + obj;
      const auto raw = read_attribute(it->second, role, TINYGLTF_TYPE_VEC2,
                                      {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                                      {TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT});
      const auto& acc = model_.accessors[it->second];
      if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !acc.normalized && !quantized_)
        fail(accessor_name(it->second, role) + " has integer components that are not normalized (glTF needs "
                                               "float or normalized unsigned byte or short texcoords)");
      if (raw.size() != 2 * vertices)
        fail(accessor_name(it->second, role) + " has " + std::to_string(raw.size() / 2) + " elements, but POSITION has " +
             std::to_string(vertices));
      std::vector<glm::vec2> uv(vertices);
      for (std::size_t i = 0; i < vertices; ++i) {
        uv[i] = glm::vec2(float(raw[2 * i]), float(raw[2 * i + 1]));
        if (!std::isfinite(uv[i].x) || !std::isfinite(uv[i].y))
          fail(accessor_name(it->second, role) + " holds a non-finite texcoord at element " + std::to_string(i));
      }
      out.push_back(std::move(uv));
    }
    return out;
  }

  // The triangles of mesh `m` in its local space (read once, reused by every node instancing it).
  const std::vector<LocalTriangle>& mesh_triangles(int m) {
    auto found = mesh_cache_.find(m);
    if (found != mesh_cache_.end()) return found->second;
    std::vector<LocalTriangle> tris;
    const auto& mesh = model_.meshes[m];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const auto& prim = mesh.primitives[p];
      const std::string obj = "mesh " + std::to_string(m) + " primitive " + std::to_string(p);
      if (prim.mode < kModePoints || prim.mode > kModeFan) fail(obj + " has unknown mode " + std::to_string(prim.mode));
      if (prim.mode < kModeTriangles) {
        ++skipped_modes_[prim.mode];
        continue;
      }
      std::uint32_t material = 0;
      if (prim.material >= 0) {
        if (std::size_t(prim.material) >= model_.materials.size())
          fail(obj + " refers to material " + std::to_string(prim.material) + ", but the file has " +
               std::to_string(model_.materials.size()) + " materials");
        material = std::uint32_t(prim.material) + 1;
      } else if (prim.material < -1) {
        fail(obj + " refers to material " + std::to_string(prim.material));
      }
      auto pos_it = prim.attributes.find("POSITION");
      if (pos_it == prim.attributes.end()) {
        ++primitives_without_position_;
        continue;
      }
      const std::string pos_role = "POSITION of " + obj;
      const auto raw = read_attribute(pos_it->second, pos_role, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT},
                                      {TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                       TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
      std::vector<glm::vec3> pos(raw.size() / 3);
      for (std::size_t i = 0; i < pos.size(); ++i) {
        pos[i] = glm::vec3(float(raw[3 * i]), float(raw[3 * i + 1]), float(raw[3 * i + 2]));
        if (!std::isfinite(pos[i].x) || !std::isfinite(pos[i].y) || !std::isfinite(pos[i].z))
          fail(accessor_name(pos_it->second, pos_role) + " holds a non-finite position at element " +
               std::to_string(i));
      }
      // NORMAL (glTF: unit VEC3 float, one per POSITION): the shading normals (docs/design.md §6).
      std::vector<glm::vec3> normals;
      if (auto normal_it = prim.attributes.find("NORMAL"); normal_it != prim.attributes.end()) {
        const std::string role = "NORMAL of " + obj;
        const auto n_raw = read_attribute(normal_it->second, role, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT},
                                          {TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT});
        if (n_raw.size() != raw.size())
          fail(accessor_name(normal_it->second, role) + " has " + std::to_string(n_raw.size() / 3) +
               " elements, but POSITION has " + std::to_string(pos.size()));
        normals.resize(pos.size());
        for (std::size_t i = 0; i < normals.size(); ++i) {
          normals[i] = glm::vec3(float(n_raw[3 * i]), float(n_raw[3 * i + 1]), float(n_raw[3 * i + 2]));
          if (!std::isfinite(normals[i].x) || !std::isfinite(normals[i].y) || !std::isfinite(normals[i].z))
            fail(accessor_name(normal_it->second, role) + " holds a non-finite normal at element " +
                 std::to_string(i));
        }
      }
      const std::vector<std::vector<glm::vec2>> uvs = read_texcoords(prim, obj, material_uv_sets_[material], pos.size());
      const SceneMaterial& mat = scene_.materials[material];
      std::vector<glm::vec4> tangents;  // TANGENT, where the material has a normal map and the primitive NORMAL
      if (mat.has_normal_map() && prim.attributes.count("TANGENT")) {
        if (normals.empty())
          ++tangents_without_normals_;  // glTF: flat normals then, and the given tangents ignored
        else
          tangents = read_tangents(prim.attributes.at("TANGENT"), "TANGENT of " + obj, pos.size());
      }
      const std::size_t first_triangle = tris.size();
      std::vector<std::array<std::uint32_t, 3>> corners;  // the primitive's triangles by vertex index
      std::vector<std::uint32_t> idx;
      if (prim.indices >= 0) {
        const std::string role = "indices of " + obj;
        idx = read_indices(prim.indices, role);
        for (std::size_t i = 0; i < idx.size(); ++i)
          if (idx[i] >= pos.size())
            fail(accessor_name(prim.indices, role) + " holds index " + std::to_string(idx[i]) + " at element " +
                 std::to_string(i) + ", but POSITION has " + std::to_string(pos.size()) + " vertices");
      } else {
        idx.resize(pos.size());
        for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = std::uint32_t(i);
      }
      auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        corners.push_back({a, b, c});
        LocalTriangle t{{pos[a], pos[b], pos[c]}, material};
        if (!normals.empty()) {
          t.has_normals = true;
          t.normal[0] = normals[a];
          t.normal[1] = normals[b];
          t.normal[2] = normals[c];
        }
        for (std::size_t slot = 0; slot < uvs.size(); ++slot) {
          t.uv[slot][0] = uvs[slot][a];
          t.uv[slot][1] = uvs[slot][b];
          t.uv[slot][2] = uvs[slot][c];
        }
        tris.push_back(t);
      };
      const std::size_t n = idx.size();
      if (prim.mode == kModeTriangles) {
        if (n % 3 != 0) ++ragged_triangle_lists_;
        for (std::size_t i = 0; i + 2 < n; i += 3) emit(idx[i], idx[i + 1], idx[i + 2]);
      } else if (prim.mode == kModeStrip) {
        for (std::size_t i = 0; i + 2 < n; ++i) {  // glTF spec: odd triangles swap to keep the winding
          if (i % 2 == 0) emit(idx[i], idx[i + 1], idx[i + 2]);
          else emit(idx[i], idx[i + 2], idx[i + 1]);
        }
      } else {
        for (std::size_t i = 1; i + 1 < n; ++i) emit(idx[0], idx[i], idx[i + 1]);
      }
      if (mat.has_normal_map()) {
        const std::vector<glm::vec2>& uv = uvs[scene_.texture_views[mat.textures.normal].uv_slot];
        add_tangents(tris.data() + first_triangle, corners, pos, normals, uv, tangents);
      }
    }
    return mesh_cache_.emplace(m, std::move(tris)).first->second;
  }

  // TANGENT (glTF: VEC4 float, one per POSITION, xyz unit, w the handedness +-1; its sign is taken).
  std::vector<glm::vec4> read_tangents(int accessor, const std::string& role, std::size_t vertices) const {
    const auto raw = read_attribute(accessor, role, TINYGLTF_TYPE_VEC4, {TINYGLTF_COMPONENT_TYPE_FLOAT},
                                    {TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT});
    if (raw.size() != 4 * vertices)
      fail(accessor_name(accessor, role) + " has " + std::to_string(raw.size() / 4) + " elements, but POSITION has " +
           std::to_string(vertices));
    std::vector<glm::vec4> out(vertices);
    for (std::size_t i = 0; i < vertices; ++i) {
      const glm::dvec4 t(raw[4 * i], raw[4 * i + 1], raw[4 * i + 2], raw[4 * i + 3]);
      if (!std::isfinite(t.x + t.y + t.z + t.w))
        fail(accessor_name(accessor, role) + " holds a non-finite tangent at element " + std::to_string(i));
      out[i] = glm::vec4(glm::vec3(t), t.w < 0.0 ? -1.0f : 1.0f);
    }
    return out;
  }

  // The corners' tangents of a normal-mapped primitive's triangles `out` (vertex indices `corners`):
  // the given TANGENT, else generated (scene/tangents.h) per vertex from NORMAL, else -- no NORMAL:
  // flat normals, as glTF asks -- per face, the flat normal becoming the triangle's NORMAL.
  void add_tangents(LocalTriangle* out, const std::vector<std::array<std::uint32_t, 3>>& corners,
                    const std::vector<glm::vec3>& pos, const std::vector<glm::vec3>& normals,
                    const std::vector<glm::vec2>& uv, std::vector<glm::vec4> tangents) {
    if (normals.empty()) {  // each corner a vertex of its own, with its face's normal
      std::vector<glm::vec3> p, n;
      std::vector<glm::vec2> t;
      std::vector<std::array<std::uint32_t, 3>> faces;
      for (const auto& c : corners) {
        const glm::vec3 flat = glm::cross(pos[c[1]] - pos[c[0]], pos[c[2]] - pos[c[0]]);  // unit at placement
        const std::uint32_t first = std::uint32_t(p.size());
        for (std::uint32_t v : c) {
          p.push_back(pos[v]);
          n.push_back(flat);
          t.push_back(uv[v]);
        }
        faces.push_back({first, first + 1, first + 2});
      }
      const GeneratedTangents g = generate_tangents(p, n, t, faces);
      tangent_fallbacks_ += g.fallbacks;
      for (std::size_t i = 0; i < corners.size(); ++i) {
        out[i].has_normals = true;
        out[i].has_tangents = true;
        for (int k = 0; k < 3; ++k) {
          out[i].normal[k] = n[3 * i + k];
          out[i].tangent[k] = g.tangents[3 * i + k];
        }
      }
      return;
    }
    if (tangents.empty()) {
      GeneratedTangents g = generate_tangents(pos, normals, uv, corners);
      tangent_fallbacks_ += g.fallbacks;
      tangents = std::move(g.tangents);
    }
    for (std::size_t i = 0; i < corners.size(); ++i) {
      out[i].has_tangents = true;
      for (int k = 0; k < 3; ++k) out[i].tangent[k] = tangents[corners[i][k]];
    }
  }

  // ------------------------------------------------------------------ nodes

  glm::dmat4 local_transform(int n) const {
    const auto& node = model_.nodes[n];
    const std::string obj = "node " + std::to_string(n) + quoted(node.name);
    glm::dmat4 m(1.0);
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) fail(obj + " matrix has " + std::to_string(node.matrix.size()) + " numbers, not 16");
      m = glm::make_mat4(node.matrix.data());  // column-major, like glTF
    } else {
      if (!node.translation.empty() && node.translation.size() != 3) fail(obj + " translation is not 3 numbers");
      if (!node.rotation.empty() && node.rotation.size() != 4) fail(obj + " rotation is not 4 numbers");
      if (!node.scale.empty() && node.scale.size() != 3) fail(obj + " scale is not 3 numbers");
      glm::dmat4 t(1.0), r(1.0), s(1.0);
      if (!node.translation.empty())
        t = glm::translate(glm::dmat4(1.0), glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
      if (!node.rotation.empty()) {
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        const double len = glm::length(q);
        if (!(len > 0.0) || !std::isfinite(len)) fail(obj + " rotation is not a unit quaternion");
        r = glm::mat4_cast(q / len);
      }
      if (!node.scale.empty()) s = glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
      m = t * r * s;
    }
    if (!all_finite(m)) fail(obj + " has a non-finite transform");
    return m;
  }

  void check_node_index(int n, const std::string& user) const {
    if (n < 0 || std::size_t(n) >= model_.nodes.size())
      fail(user + " refers to node " + std::to_string(n) + ", but the file has " +
           std::to_string(model_.nodes.size()) + " nodes");
  }

  std::vector<int> root_nodes() {
    if (model_.defaultScene >= 0 || !model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (std::size_t(s) >= model_.scenes.size())
        fail("default scene " + std::to_string(s) + " does not exist (the file has " +
             std::to_string(model_.scenes.size()) + " scenes)");
      for (int n : model_.scenes[s].nodes) check_node_index(n, "scene " + std::to_string(s));
      return model_.scenes[s].nodes;
    }
    std::vector<bool> is_child(model_.nodes.size(), false);  // no scenes: every root node
    for (std::size_t n = 0; n < model_.nodes.size(); ++n)
      for (int c : model_.nodes[n].children) {
        check_node_index(c, "node " + std::to_string(n));
        is_child[c] = true;
      }
    std::vector<int> roots;
    for (std::size_t n = 0; n < model_.nodes.size(); ++n)
      if (!is_child[n]) roots.push_back(int(n));
    return roots;
  }

  // Depth-first over the default scene, with an explicit stack (deep hierarchies), an on-stack
  // set (cycles) and a visited set: glTF nodes form disjoint strict trees, and a node reached twice
  // (two parents, or listed twice) would let a small file instance a mesh 2^depth times.
  void traverse() {
    struct Frame {
      int node;
      glm::dmat4 world;
      std::size_t next_child;
    };
    std::vector<char> on_stack(model_.nodes.size(), 0), visited(model_.nodes.size(), 0);
    for (int root : root_nodes()) {
      std::vector<Frame> stack;
      auto enter = [&](int n, const glm::dmat4& parent) {
        if (on_stack[n]) fail("node " + std::to_string(n) + " is its own ancestor (cycle in the node hierarchy)");
        if (visited[n])
          fail("node " + std::to_string(n) +
               " is reached twice (it has two parents or is listed twice; glTF nodes must form trees)");
        on_stack[n] = visited[n] = 1;
        const glm::dmat4 world = parent * local_transform(n);
        if (!all_finite(world)) fail("node " + std::to_string(n) + " has a non-finite world transform");
        visit(n, parent, world);
        stack.push_back(Frame{n, world, 0});
      };
      enter(root, glm::dmat4(1.0));
      while (!stack.empty()) {
        Frame& top = stack.back();
        const auto& children = model_.nodes[top.node].children;
        if (top.next_child == children.size()) {
          on_stack[top.node] = 0;
          stack.pop_back();
          continue;
        }
        const int child = children[top.next_child++];
        check_node_index(child, "node " + std::to_string(top.node));
        const glm::dmat4 parent = top.world;  // `top` dies if the stack grows
        enter(child, parent);
      }
    }
  }

  void visit(int n, const glm::dmat4& parent, const glm::dmat4& world) {
    const auto& node = model_.nodes[n];
    const std::string obj = "node " + std::to_string(n) + quoted(node.name);
    if (node.camera != -1) {
      if (node.camera < 0 || std::size_t(node.camera) >= model_.cameras.size())
        fail(obj + " refers to camera " + std::to_string(node.camera) + ", but the file has " +
             std::to_string(model_.cameras.size()) + " cameras");
      take_camera(node.camera, n, parent, world);
    }
    if (const auto* light = extension(node.extensions, "KHR_lights_punctual", "light")) {
      if (!light->IsInt()) fail(obj + " KHR_lights_punctual.light is not an index");
      take_light(light->GetNumberAsInt(), n, world);
    }
    if (node.mesh == -1) return;
    if (node.mesh < 0 || std::size_t(node.mesh) >= model_.meshes.size())
      fail(obj + " refers to mesh " + std::to_string(node.mesh) + ", but the file has " +
           std::to_string(model_.meshes.size()) + " meshes");
    const bool flip = glm::determinant(glm::dmat3(world)) < 0.0;  // mirrored: keep fronts in front
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));  // normals: inverse transpose
    for (const LocalTriangle& t : mesh_triangles(node.mesh)) {
      if (material_cut_away_[t.material]) {  // alphaMode MASK cuts all of it away
        ++cut_away_;
        continue;
      }
      SceneTriangle out;
      for (int k = 0; k < 3; ++k) out.p[k] = glm::vec3(world * glm::dvec4(glm::dvec3(t.p[k]), 1.0));
      for (std::uint32_t slot = 0; slot < BP_MAX_UV_SLOTS; ++slot)
        for (int k = 0; k < 3; ++k) out.uv[slot][k] = t.uv[slot][k];
      if (flip)
        for (auto& uv : out.uv) std::swap(uv[1], uv[2]);
      if (t.has_normals) {
        out.has_normals = true;
        for (int k = 0; k < 3; ++k) {
          const glm::dvec3 n = normal_matrix * glm::dvec3(t.normal[k]);
          const double len = glm::length(n);
          // a zero NORMAL (or one the transform crushes) leaves that corner to the flat normal, set below
          out.normal[k] = len > 0.0 && std::isfinite(len) ? glm::vec3(n / len) : glm::vec3(0.0f);
        }
        if (flip) std::swap(out.normal[1], out.normal[2]);
      }
      if (flip) std::swap(out.p[1], out.p[2]);
      out.material = t.material;
      const glm::dvec3 a(out.p[0]), b(out.p[1]), c(out.p[2]);
      const double cross = glm::length(glm::cross(b - a, c - a));
      const double longest = std::max({glm::length(b - a), glm::length(c - a), glm::length(c - b)});
      bool finite = true;
      for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(out.p[k].x) && std::isfinite(out.p[k].y) && std::isfinite(out.p[k].z);
      if (!finite) fail(obj + " places mesh " + std::to_string(node.mesh) + " at non-finite positions");
      if (!(cross > 1e-10 * longest * longest)) {  // zero area (up to float noise of collinear points)
        ++degenerate_;
        continue;
      }
      if (out.has_normals) {
        const glm::vec3 flat = glm::vec3(glm::normalize(glm::cross(b - a, c - a)));
        for (glm::vec3& n : out.normal)
          if (n == glm::vec3(0.0f)) {
            n = flat;
            ++zero_normals_;
          }
      }
      if (t.has_tangents) place_tangents(t, world, flip, out);
      scene_.triangles.push_back(out);
    }
  }

  // A normal-mapped triangle's tangents in the world: xyz by the node's matrix (a tangent is a
  // direction in the surface, not a normal), made orthogonal to the world NORMAL again; a mirroring
  // node reverses the handedness w (B = w cross(N, T) must stay the mirrored bitangent), and swaps
  // corners 1 and 2 as it does every corner's attributes.
  void place_tangents(const LocalTriangle& t, const glm::dmat4& world, bool flip, SceneTriangle& out) {
    for (int k = 0; k < 3; ++k) {
      const int corner = flip && k > 0 ? 3 - k : k;  // out.normal is already in the swapped order
      const glm::vec3 n = out.normal[corner];
      const glm::dvec3 moved = glm::dmat3(world) * glm::dvec3(glm::vec3(t.tangent[k]));
      glm::vec3 tangent = glm::vec3(moved - glm::dvec3(n) * glm::dot(glm::dvec3(n), moved));  // Gram-Schmidt
      const float len = glm::length(tangent);
      if (len > 1e-12f && std::isfinite(len)) {
        tangent /= len;
      } else {
        tangent = any_tangent(n);
        ++tangent_fallbacks_;
      }
      out.tangent[corner] = glm::vec4(tangent, flip ? -t.tangent[k].w : t.tangent[k].w);
    }
  }

  // Every perspective camera node, in traversal order; the first is the plain render's view.
  void take_camera(int c, int n, const glm::dmat4& parent, const glm::dmat4& world) {
    const auto& cam = model_.cameras[c];
    const std::string obj = "camera " + std::to_string(c) + quoted(cam.name);
    if (cam.type == "orthographic") {
      scene_.warnings.push_back(obj + " (node " + std::to_string(n) + ") is orthographic; ignored");
      return;
    }
    if (cam.type != "perspective") fail(obj + " has unknown type \"" + cam.type + "\"");
    const double yfov = cam.perspective.yfov, aspect = cam.perspective.aspectRatio;
    if (!(yfov > 0.0 && yfov < M_PI)) fail(obj + " has yfov " + std::to_string(yfov) + " outside (0, pi)");
    if (!(aspect >= 0.0 && std::isfinite(float(aspect)))) fail(obj + " has aspectRatio " + std::to_string(aspect));
    const std::optional<SceneCamera> view = camera_from_world(world, yfov, aspect);
    if (!view) fail("node " + std::to_string(n) + " gives " + obj + " a degenerate orientation");
    SceneCameraNode node{n, model_.nodes[n].name, cam.name, *view, std::nullopt, ""};
    // An animation that cannot be played fails only the render that asks for it (--camera-animation).
    try {
      node.animation = camera_animation(n, parent);
    } catch (const SceneError& e) {
      node.animation_error = e.what();
    }
    scene_.camera_nodes.push_back(node);
    if (scene_.camera_nodes.size() == 1) scene_.camera = *view;
  }

  // The first animation with translation or rotation channels on node n (scene/scene_cameras.h).
  std::optional<CameraAnimation> camera_animation(int n, const glm::dmat4& parent) const {
    const auto& node = model_.nodes[n];
    for (std::size_t a = 0; a < model_.animations.size(); ++a) {
      const auto& animation = model_.animations[a];
      CameraAnimation out;
      out.name = "animation " + std::to_string(a) + quoted(animation.name);
      for (std::size_t ch = 0; ch < animation.channels.size(); ++ch) {
        const auto& channel = animation.channels[ch];
        if (channel.target_node != n || (channel.target_path != "translation" && channel.target_path != "rotation"))
          continue;
        const std::string obj = out.name + " channel " + std::to_string(ch);
        if (!node.matrix.empty()) fail(obj + " animates node " + std::to_string(n) + ", which has a matrix (glTF needs TRS)");
        (channel.target_path == "rotation" ? out.rotation_track : out.translation_track) =
            camera_track(animation, channel.sampler, obj, channel.target_path == "rotation");
      }
      if (!out.translation_track && !out.rotation_track) continue;
      out.parent_world = parent;
      if (!node.translation.empty()) out.translation = glm::dvec3(node.translation[0], node.translation[1], node.translation[2]);
      if (!node.rotation.empty())
        out.rotation = glm::normalize(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
      if (!node.scale.empty()) out.scale = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
      return out;
    }
    return std::nullopt;
  }

  CameraTrack camera_track(const tinygltf::Animation& animation, int s, const std::string& obj, bool rotation) const {
    if (s < 0 || std::size_t(s) >= animation.samplers.size())
      fail(obj + " refers to sampler " + std::to_string(s) + ", but the animation has " +
           std::to_string(animation.samplers.size()));
    const auto& sampler = animation.samplers[s];
    if (sampler.interpolation != "LINEAR" && sampler.interpolation != "STEP")
      fail(obj + " has interpolation " + sampler.interpolation + " (only LINEAR and STEP are read)");
    CameraTrack track;
    track.step = sampler.interpolation == "STEP";
    track.times = read_accessor(sampler.input, obj + " input", TINYGLTF_TYPE_SCALAR, {TINYGLTF_COMPONENT_TYPE_FLOAT});
    const int components = rotation ? 4 : 3;
    const std::vector<double> values = read_accessor(sampler.output, obj + " output",
                                                     rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3,
                                                     {TINYGLTF_COMPONENT_TYPE_FLOAT});
    if (track.times.empty()) fail(obj + " has no keyframes");
    if (values.size() != track.times.size() * components)
      fail(obj + " has " + std::to_string(track.times.size()) + " keyframe times but " +
           std::to_string(values.size() / components) + " values");
    for (std::size_t k = 0; k < track.times.size(); ++k) {
      if (!std::isfinite(track.times[k]) || (k > 0 && !(track.times[k] > track.times[k - 1])))
        fail(obj + " keyframe times are not finite and strictly increasing at keyframe " + std::to_string(k));
      glm::dvec4 v(0.0);
      for (int c = 0; c < components; ++c) v[c] = values[k * components + c];
      if (!std::isfinite(v.x + v.y + v.z + v.w) || (rotation && !(glm::length(v) > 0.0)))
        fail(obj + " keyframe " + std::to_string(k) + " is not finite" + (rotation ? " or not a rotation" : ""));
      track.values.push_back(rotation ? v / glm::length(v) : v);
    }
    return track;
  }

  // KHR_lights_punctual: position from the node, direction its -z; intensity in candela (lm/sr) or,
  // for directional lights, lux (lm/m^2), made radiometric (W/sr, W/m^2) at 683 lm/W -- the factor
  // Blender's exporter multiplies watts by (a sun's W/m^2 alike).
  static constexpr double kLumensPerWatt = 683.0;
  void take_light(int l, int n, const glm::dmat4& world) {
    const std::string obj = "KHR_lights_punctual light " + std::to_string(l);
    if (l < 0 || std::size_t(l) >= model_.lights.size())
      fail("node " + std::to_string(n) + " refers to " + obj + ", but the file has " +
           std::to_string(model_.lights.size()) + " lights");
    const auto& light = model_.lights[l];
    const std::string name = obj + quoted(light.name);
    if (light.type != "point" && light.type != "spot" && light.type != "directional")
      fail(name + " has unknown type \"" + light.type + "\"");
    ScenePunctualLight out;
    out.name = light.name;
    out.kind = light.type == "spot"          ? ScenePunctualLight::Kind::spot
               : light.type == "directional" ? ScenePunctualLight::Kind::directional
                                             : ScenePunctualLight::Kind::point;
    glm::dvec3 colour(1.0);
    if (!light.color.empty()) {
      if (light.color.size() != 3) fail(name + " color is not an array of 3 numbers");
      colour = glm::dvec3(light.color[0], light.color[1], light.color[2]);
    }
    if (!(light.intensity >= 0.0 && std::isfinite(light.intensity)))
      fail(name + " has intensity " + std::to_string(light.intensity) + " (expected a finite number >= 0)");
    if (!(colour.x >= 0.0 && colour.y >= 0.0 && colour.z >= 0.0 && std::isfinite(colour.x + colour.y + colour.z)))
      fail(name + " has a color outside [0, inf)");
    out.intensity = glm::vec3(colour * (light.intensity / kLumensPerWatt));
    if (out.kind == ScenePunctualLight::Kind::spot) {
      const double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
      if (!(inner >= 0.0 && inner < outer && outer <= 0.5 * M_PI))
        fail(name + " has cone angles inner " + std::to_string(inner) + ", outer " + std::to_string(outer) +
             " (glTF needs 0 <= inner < outer <= pi/2)");
      out.inner_cone = float(inner);
      out.outer_cone = float(outer);
    }
    out.position = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
    const glm::dvec3 axis = glm::dmat3(world) * glm::dvec3(0, 0, -1);
    if (!(glm::length(axis) > 0.0) || !all_finite(world))
      fail("node " + std::to_string(n) + " gives " + name + " a degenerate orientation");
    out.direction = glm::vec3(glm::normalize(axis));
    scene_.lights.push_back(out);
  }

  // ------------------------------------------------------------------ the end

  void finish() {
    for (const auto& [mode, count] : skipped_modes_)
      scene_.warnings.push_back("skipped " + std::to_string(count) + " primitive(s) of mode " + kModeNames[mode] +
                                "; only triangles are rendered");
    if (primitives_without_position_)
      scene_.warnings.push_back("skipped " + std::to_string(primitives_without_position_) +
                                " primitive(s) without POSITION");
    if (ragged_triangle_lists_)
      scene_.warnings.push_back(std::to_string(ragged_triangle_lists_) +
                                " TRIANGLES primitive(s) have an index count that is not a multiple of 3; "
                                "the extra indices are ignored");
    if (degenerate_)
      scene_.warnings.push_back("dropped " + std::to_string(degenerate_) + " degenerate (zero-area) triangle(s)");
    if (zero_normals_)
      scene_.warnings.push_back(std::to_string(zero_normals_) +
                                " triangle corner(s) have a zero NORMAL; the flat normal is used there");
    if (cut_away_)
      scene_.warnings.push_back("dropped " + std::to_string(cut_away_) +
                                " triangle(s) whose alphaMode MASK material is below its alphaCutoff everywhere");
    if (tangent_fallbacks_)
      scene_.warnings.push_back(std::to_string(tangent_fallbacks_) +
                                " normal-mapped vertex tangent(s) have no direction from their texcoords or TANGENT; "
                                "any tangent orthogonal to the normal is used there");
    if (tangents_without_normals_)
      scene_.warnings.push_back(std::to_string(tangents_without_normals_) +
                                " normal-mapped primitive(s) have TANGENT but no NORMAL; as glTF asks, flat normals "
                                "and generated tangents are used");
    if (missing_texcoords_)
      scene_.warnings.push_back(std::to_string(missing_texcoords_) +
                                " textured primitive(s) lack the TEXCOORD set their material reads; it reads (0, 0) there");
    if (scene_.triangles.empty()) fail("scene has no triangles");
    for (const auto& t : scene_.triangles)
      for (const auto& p : t.p) scene_.bounds.grow(p);
    for (const auto& node : model_.nodes) scene_.node_names.push_back(node.name);
    if (scene_.camera_nodes.empty()) {
      // Default view (gltf_loader.h): from +z, the bounding sphere fits the vertical field of view.
      SceneCamera cam;
      const float radius = std::max(0.5f * glm::length(scene_.bounds.extent()), 1e-6f);
      const float distance = radius / std::sin(0.5f * cam.yfov);
      cam.forward = glm::vec3(0, 0, -1);
      cam.up = glm::vec3(0, 1, 0);
      cam.position = scene_.bounds.centre() + glm::vec3(0, 0, distance);
      cam.from_file = false;
      scene_.camera = cam;
      scene_.warnings.push_back("no camera in file; using a default view");
    }
    if (!scene_.has_light()) scene_.warnings.push_back("no emitter: the image will be black");
  }

  std::string path_;
  std::optional<std::string> base_dir_;
  tinygltf::Model model_;
  Scene scene_;
  std::map<int, std::vector<LocalTriangle>> mesh_cache_;
  std::map<int, ImageTexels> decoded_images_;
  std::vector<std::vector<int>> material_uv_sets_;
  bool quantized_ = false;  // the file uses KHR_mesh_quantization: integer vertex attributes (read_attribute)
  std::vector<bool> material_cut_away_;  // per scene material: alphaMode MASK with a constant alpha below the cutoff  // per scene material: the glTF TEXCOORD sets of its uv slots
  std::map<int, std::size_t> skipped_modes_;
  std::size_t primitives_without_position_ = 0, ragged_triangle_lists_ = 0, degenerate_ = 0, zero_normals_ = 0,
              missing_texcoords_ = 0, cut_away_ = 0, tangent_fallbacks_ = 0, tangents_without_normals_ = 0;
};

}  // namespace

Scene load_gltf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(one_line(path + ": cannot open file (" + std::strerror(errno) + ")"));
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw SceneError(one_line(path + ": read error"));
  std::string base_dir = std::filesystem::path(path).parent_path().string();
  if (base_dir.empty()) base_dir = ".";
  const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;  // by content, not name
  return Loader(path, base_dir).load(bytes, glb);
}

Scene load_gltf_from_memory(const std::string& bytes, const std::string& display_name, bool binary) {
  return Loader(display_name, std::nullopt).load(std::vector<unsigned char>(bytes.begin(), bytes.end()), binary);
}

}  // namespace bp

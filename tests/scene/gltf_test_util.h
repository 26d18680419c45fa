// Helpers shared by the scene tests.
#pragma once
#include "scene/scene.h"

#include <glm/glm.hpp>
#include <cstdint>
#include <string>

namespace bp::test {

inline std::string gltf_sample(const std::string& name) { return std::string(BP_SOURCE_DIR) + "/tests/data/gltf/samples/" + name; }
inline std::string test_file(const std::string& rel) { return std::string(BP_SOURCE_DIR) + "/tests/data/gltf/" + rel; }
inline std::string scene_file(const std::string& name) { return std::string(BP_SOURCE_DIR) + "/scenes/" + name; }

inline glm::vec3 normal_of(const SceneTriangle& t) { return glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]); }

// A GoogleTest parameter name from a data file name: "node-two-parents.gltf" -> "node_two_parents".
inline std::string test_name_from_file(std::string name) {
  name = name.substr(0, name.find('.'));
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name;
}

// RFC 4648 base64, for data: URIs.
inline std::string base64(const std::string& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = std::uint8_t(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= std::uint8_t(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= std::uint8_t(bytes[i + 2]);
    out += digits[v >> 18 & 63];
    out += digits[v >> 12 & 63];
    out += i + 1 < bytes.size() ? digits[v >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? digits[v & 63] : '=';
  }
  return out;
}

inline bool has_warning(const Scene& s, const std::string& part) {
  for (const auto& w : s.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace bp::test

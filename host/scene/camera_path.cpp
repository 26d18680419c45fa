#include "scene/camera_path.h"

#include "scene/gltf_loader.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace bp {
namespace {

glm::dvec3 vector_of(const nlohmann::json& key, const char* name, const std::string& where) {
  const nlohmann::json& v = key.at(name);
  if (!v.is_array() || v.size() != 3) throw SceneError(where + " \"" + name + "\" is not an array of 3 numbers");
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c) {
    if (!v[c].is_number() || !std::isfinite(v[c].get<double>()))
      throw SceneError(where + " \"" + name + "\" is not an array of 3 finite numbers");
    out[c] = v[c].get<double>();
  }
  return out;
}

}  // namespace

std::vector<SceneCamera> read_camera_path(const std::string& path, const SceneCamera& defaults) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the camera path file");
  nlohmann::json keys;
  try {
    keys = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    throw SceneError(path + ": not JSON (expected an array of {\"position\", \"target\", \"up\", \"yfov\"} keys)");
  }
  if (!keys.is_array()) throw SceneError(path + ": expected an array of {\"position\", \"target\", \"up\", \"yfov\"} keys");
  if (keys.empty()) throw SceneError(path + ": the camera path is empty (no keys)");
  std::vector<SceneCamera> views;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const nlohmann::json& key = keys[k];
    const std::string where = path + ": key " + std::to_string(k);
    if (!key.is_object() || !key.contains("position") || !key.contains("target"))
      throw SceneError(where + " is not an object with \"position\" and \"target\"");
    const glm::dvec3 position = vector_of(key, "position", where), target = vector_of(key, "target", where);
    const glm::dvec3 up = key.contains("up") ? vector_of(key, "up", where) : glm::dvec3(0, 1, 0);
    double yfov = defaults.yfov;
    if (key.contains("yfov")) {
      if (!key["yfov"].is_number()) throw SceneError(where + " \"yfov\" is not a number");
      yfov = key["yfov"].get<double>();
    }
    if (!(yfov > 0.0 && yfov < M_PI)) throw SceneError(where + " \"yfov\" " + std::to_string(yfov) + " is outside (0, pi)");
    const double distance = glm::length(target - position);
    if (!(distance > 0.0)) throw SceneError(where + " has its target at its position");
    const glm::dvec3 forward = (target - position) / distance;
    const glm::dvec3 ortho_up = up - glm::dot(up, forward) * forward;
    if (!(glm::length(ortho_up) > 1e-9 * std::max(1.0, glm::length(up))))
      throw SceneError(where + " has \"up\" along its view direction (or zero)");
    SceneCamera camera = defaults;
    camera.position = glm::vec3(position);
    camera.forward = glm::vec3(forward);
    camera.up = glm::vec3(glm::normalize(ortho_up));
    camera.yfov = float(yfov);
    camera.from_file = true;
    views.push_back(camera);
  }
  return views;
}

}  // namespace bp

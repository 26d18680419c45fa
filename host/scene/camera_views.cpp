#include "scene/camera_views.h"

#include "scene/camera_path.h"
#include "scene/gltf_loader.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bp {
namespace {

std::string quoted_name(const std::string& name) { return name.empty() ? "" : " '" + name + "'"; }

std::string camera_list(const Scene& scene) {
  std::string out;
  for (std::size_t k = 0; k < scene.camera_nodes.size(); ++k) {
    const SceneCameraNode& c = scene.camera_nodes[k];
    out += (k ? ", " : "") + std::to_string(k) + (c.name.empty() ? "" : " '" + c.name + "'");
  }
  return out.empty() ? "none" : out;
}

// --camera INDEX|NAME: an index into the camera nodes, else a node's name, else a camera's name.
const SceneCameraNode& find_camera_node(const Scene& scene, const std::string& wanted) {
  const std::string cameras = " (camera nodes of " + scene.source + ": " + camera_list(scene) + ")";
  if (!wanted.empty() && std::all_of(wanted.begin(), wanted.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    const std::size_t index = wanted.size() > 9 ? std::size_t(-1) : std::stoul(wanted);
    if (index >= scene.camera_nodes.size()) throw std::invalid_argument("--camera " + wanted + ": no such camera" + cameras);
    return scene.camera_nodes[index];
  }
  for (const SceneCameraNode& c : scene.camera_nodes)
    if (c.name == wanted) return c;
  for (std::size_t n = 0; n < scene.node_names.size(); ++n)
    if (scene.node_names[n] == wanted)
      throw std::invalid_argument("--camera " + wanted + ": node " + std::to_string(n) + " '" + wanted +
                                  "' holds no perspective camera" + cameras);
  for (const SceneCameraNode& c : scene.camera_nodes)
    if (c.camera_name == wanted) return c;
  throw std::invalid_argument("--camera " + wanted + ": no camera node or camera of that name" + cameras);
}

glm::dvec4 track_value(const CameraTrack& track, double t, bool rotation) {
  const std::vector<double>& times = track.times;
  if (t <= times.front()) return track.values.front();
  if (t >= times.back()) return track.values.back();
  const std::size_t next = std::size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin());
  const std::size_t prev = next - 1;
  if (track.step) return track.values[prev];
  const double f = (t - times[prev]) / (times[next] - times[prev]);
  const glm::dvec4 a = track.values[prev], b = track.values[next];
  if (!rotation) return a + f * (b - a);
  const glm::dquat q = glm::slerp(glm::dquat(a.w, a.x, a.y, a.z), glm::dquat(b.w, b.x, b.y, b.z), f);
  return glm::dvec4(q.x, q.y, q.z, q.w);
}

}  // namespace

double CameraAnimation::start() const {
  double t = 1e300;
  if (translation_track) t = std::min(t, translation_track->times.front());
  if (rotation_track) t = std::min(t, rotation_track->times.front());
  return t;
}

double CameraAnimation::end() const {
  double t = -1e300;
  if (translation_track) t = std::max(t, translation_track->times.back());
  if (rotation_track) t = std::max(t, rotation_track->times.back());
  return t;
}

std::optional<SceneCamera> camera_from_world(const glm::dmat4& world, double yfov, double aspect) {
  const glm::dvec3 position(world * glm::dvec4(0, 0, 0, 1));
  glm::dvec3 forward = glm::normalize(glm::dmat3(world) * glm::dvec3(0, 0, -1));
  glm::dvec3 up = glm::dmat3(world) * glm::dvec3(0, 1, 0);
  up = glm::normalize(up - glm::dot(up, forward) * forward);
  if (!std::isfinite(forward.x + forward.y + forward.z + up.x + up.y + up.z + position.x + position.y + position.z))
    return std::nullopt;
  SceneCamera camera;
  camera.position = glm::vec3(position);
  camera.forward = glm::vec3(forward);
  camera.up = glm::vec3(up);
  camera.yfov = float(yfov);
  camera.aspect = float(aspect);
  camera.from_file = true;
  return camera;
}

SceneCamera sample_camera_animation(const SceneCameraNode& node, double t) {
  const CameraAnimation& a = *node.animation;
  glm::dvec3 translation = a.translation;
  glm::dquat rotation = a.rotation;
  if (a.translation_track) translation = glm::dvec3(track_value(*a.translation_track, t, false));
  if (a.rotation_track) {
    const glm::dvec4 q = track_value(*a.rotation_track, t, true);
    rotation = glm::normalize(glm::dquat(q.w, q.x, q.y, q.z));
  }
  const glm::dmat4 local = glm::translate(glm::dmat4(1.0), translation) * glm::mat4_cast(rotation) *
                           glm::scale(glm::dmat4(1.0), a.scale);
  const std::optional<SceneCamera> camera = camera_from_world(a.parent_world * local, node.view.yfov, node.view.aspect);
  if (!camera)
    throw std::invalid_argument(a.name + " gives camera node " + std::to_string(node.node) +
                                " a degenerate orientation at t = " + std::to_string(t) + " s");
  return *camera;
}

std::vector<double> animation_sample_times(const CameraAnimation& animation, double fps) {
  const double start = animation.start(), length = animation.end() - start;
  // A frame whose time is within a millionth of a frame of the end still counts (float keyframe times).
  const std::size_t frames = std::size_t(std::floor(length * fps + 1e-6)) + 1;
  std::vector<double> times(frames);
  for (std::size_t k = 0; k < frames; ++k) times[k] = start + double(k) / fps;
  return times;
}

std::vector<SceneCamera> select_views(const Scene& scene, const ViewRequest& r) {
  if (r.all_cameras + !r.path_file.empty() + (r.animation || !r.camera.empty() ? 1 : 0) > 1)
    throw std::invalid_argument("give one view source: --camera [with --camera-animation], --cameras all or --camera-path");
  if (!(r.fps > 0.0) || !std::isfinite(r.fps)) throw std::invalid_argument("--fps must be a number > 0");
  if (!r.path_file.empty()) return read_camera_path(r.path_file, scene.camera);
  if (r.all_cameras) {
    if (scene.camera_nodes.empty())
      throw std::invalid_argument("--cameras all: " + scene.source + " has no perspective camera node");
    std::vector<SceneCamera> views;
    for (const SceneCameraNode& c : scene.camera_nodes) views.push_back(c.view);
    return views;
  }
  if (r.camera.empty() && !r.animation) return {scene.camera};
  if (scene.camera_nodes.empty())
    throw std::invalid_argument((r.animation ? std::string("--camera-animation") : "--camera " + r.camera) + ": " +
                                scene.source + " has no perspective camera node");
  const SceneCameraNode& node = find_camera_node(scene, r.camera.empty() ? "0" : r.camera);
  if (!r.animation) return {node.view};
  if (!node.animation_error.empty()) throw SceneError(node.animation_error);
  if (!node.animation)
    throw std::invalid_argument("--camera-animation: camera node " + std::to_string(node.node) +
                                quoted_name(node.name) + " is not animated (no translation or rotation channel)");
  std::vector<SceneCamera> views;
  for (double t : animation_sample_times(*node.animation, r.fps)) views.push_back(sample_camera_animation(node, t));
  return views;
}

}  // namespace bp

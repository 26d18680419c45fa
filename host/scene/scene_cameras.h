// The camera nodes of a glTF scene and their animations (walkthroughs, docs/design.md §8): what
// --camera, --cameras all and --camera-animation choose from (scene/camera_views.h).
#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <optional>
#include <string>
#include <vector>

namespace bp {

struct SceneCamera {
  glm::vec3 position{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit; the view direction
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  float yfov = 0.6911f;                  // vertical field of view, radians
  float aspect = 0.0f;                   // width/height from the file; 0 = not given
  bool from_file = false;                // false: a default view made by the loader
};

// One animated property of a camera node: keyframe times (seconds, increasing) and values
// (translation x, y, z, 0 or rotation quaternion x, y, z, w, as glTF stores them).
struct CameraTrack {
  std::vector<double> times;
  std::vector<glm::dvec4> values;
  bool step = false;  // glTF STEP interpolation; else LINEAR (slerp for rotations)
};

// A glTF animation's channels on one camera node. The node's local transform is T·R·S with T and R
// from the tracks where they have one, else its rest pose; its parent's world transform is fixed
// (animated ancestors are not followed).
struct CameraAnimation {
  std::string name;  // animation N "name", for messages
  glm::dmat4 parent_world{1.0};
  glm::dvec3 translation{0.0}, scale{1.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  std::optional<CameraTrack> translation_track, rotation_track;
  double start() const;  // the earliest keyframe of its tracks
  double end() const;    // the latest
};

// A node with a perspective camera, in the order the loader meets them (depth-first, the default
// scene's roots in order): index k of this list is --camera k.
struct SceneCameraNode {
  int node = 0;
  std::string name;         // the node's name ("" if none)
  std::string camera_name;  // the glTF camera's name ("" if none)
  SceneCamera view;         // at the node's rest pose
  std::optional<CameraAnimation> animation;  // the first glTF animation with channels on this node
  std::string animation_error;  // why that animation cannot be played (CUBICSPLINE, bad keyframes), if so
};

}  // namespace bp

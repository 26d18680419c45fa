// The views of a render (walkthroughs, docs/design.md §8): one camera node, every camera node, a camera
// path file, or a camera node's animation sampled at a frame rate.
#pragma once
#include "scene/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace bp {

// What --camera, --cameras all, --camera-path and --camera-animation ask for.
struct ViewRequest {
  std::string camera;       // --camera INDEX|NAME (a camera node's index in Scene::camera_nodes, or its
                            // node's or camera's name); empty: the scene's view (the first camera node)
  bool all_cameras = false; // --cameras all: every camera node at its rest pose, in scene order
  std::string path_file;    // --camera-path FILE.json
  bool animation = false;   // --camera-animation: the chosen camera node's animation
  double fps = 24.0;        // frames per second of an animation's samples
  // Several frames (PREFIX_0000...) rather than one image: every source but --camera.
  bool frames() const { return all_cameras || !path_file.empty() || animation; }
};

// The views the request names. Throws std::invalid_argument (a bad option: unknown camera, a node
// without a camera, a camera without an animation, fps <= 0) and SceneError (a camera path file
// or an animation that cannot be used), each one line.
std::vector<SceneCamera> select_views(const Scene& scene, const ViewRequest& request);

// The camera a node with this world transform holds (looking down its -z, up its +y); nullopt when
// the transform crushes the view direction or the up vector.
std::optional<SceneCamera> camera_from_world(const glm::dmat4& world, double yfov, double aspect);

// The animated node's camera at time t (clamped to the keyframes: before the first the first value,
// after the last the last). LINEAR interpolates translations linearly and rotations by slerp; STEP
// holds the value of the last keyframe at or before t.
SceneCamera sample_camera_animation(const SceneCameraNode& node, double t);
// The times an animation is sampled at: start + k / fps for k = 0, 1, ... while <= end (one frame
// when start = end).
std::vector<double> animation_sample_times(const CameraAnimation& animation, double fps);

}  // namespace bp

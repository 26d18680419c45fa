// --camera-path FILE.json: a walkthrough's views given as keys (docs/design.md §8).
#pragma once
#include "scene/scene_cameras.h"

#include <string>
#include <vector>

namespace bp {

// The file is a JSON array of keys, one view each:
//   [{"position": [x, y, z], "target": [x, y, z], "up": [x, y, z], "yfov": radians}, ...]
// "up" defaults to [0, 1, 0] and "yfov" to `defaults.yfov`; the aspect is `defaults.aspect`.
// Throws SceneError (one line naming the file and the key) for a file that cannot be read, is not
// such an array, is empty, or has a key with target = position, up along the view, yfov outside
// (0, pi), or a non-finite number.
std::vector<SceneCamera> read_camera_path(const std::string& path, const SceneCamera& defaults);

}  // namespace bp

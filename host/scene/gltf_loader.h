// glTF 2.0 (.gltf with embedded or external buffers, .glb) -> Scene, with the mapping of DESIGN.md §6.
#pragma once
#include "scene/scene.h"
#include <stdexcept>
#include <string>

namespace bp {

// A file the loader cannot use. what() is one line that names the file and the offending object,
// e.g. "scenes/x.gltf: accessor 3 (POSITION of mesh 0 primitive 1) runs past the end of buffer view 2".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Scene load_gltf(const std::string& path);

}  // namespace bp

// glTF 2.0 (.gltf with embedded or external buffers, .glb) -> Scene, with the mapping of docs/design.md §6.
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

// What load_gltf gives:
// * materials: index 0 is always the default material ("default": kd 0.8 grey, Lambert), used by
//   primitives without one; file material i is at index i + 1. Mapping as docs/design.md §6; a material
//   with max(kd + ks) > 1 is scaled down to 1 with a warning.
// * triangles: the default scene (`scene`, else scene 0, else every root node), world space, one
//   copy per node that instances a mesh. TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN are
//   triangulated; other modes are skipped with one warning per mode. Mirroring node transforms
//   swap two vertices so the front face stays front. Zero-area triangles are dropped (one warning).
// * camera: the first perspective camera met depth-first in the default scene (orthographic ones
//   are skipped with a warning). Without one, a default view (camera.from_file = false, warning
//   "no camera in file; using a default view"): from the +z side of the bounds centre, looking
//   down -z with up +y, at the distance r / sin(yfov / 2) where the bounding sphere (radius r, half
//   the bounds diagonal) just fits the default yfov (SceneCamera's, 0.6911 rad).
// * camera_nodes: every perspective camera node in the same order, each with the first animation
//   that has translation or rotation channels on it (LINEAR or STEP). One that cannot be played
//   (CUBICSPLINE, bad keyframes) leaves its message in animation_error: it fails only a render
//   that asks for that animation.
// * warnings also say when no triangle emits ("no emitter: the image will be black").
// * refused: any index or byte range out of bounds, node cycles, non-finite positions or
//   transforms, non-float positions, sparse indices out of range or not increasing, buffer URIs
//   that leave the file's folder (absolute, "..", other schemes), and scenes with no triangles.
//   Textures are never read (images are accepted and ignored).
Scene load_gltf(const std::string& path);

// The same from bytes in memory (the fuzz target's entry point): `binary` reads them as a .glb,
// otherwise as .gltf JSON; `display_name` stands for the path in messages and Scene::source.
// Buffers may only be embedded (data: URIs, the .glb BIN chunk): any other URI is refused.
Scene load_gltf_from_memory(const std::string& bytes, const std::string& display_name, bool binary);

}  // namespace bp

// The light tree of light selection (kernels/shared/light_tree.h): a BVH over the scene's lights
// whose nodes bound power, position and orientation, and the per-patch receivers it is queried with.
#pragma once
#include "kernels/shared/light_tree.h"
#include "scene/lights.h"
#include "scene/patches.h"
#include "scene/scene.h"
#include <vector>

namespace bp {

// Builds the tree over lights.lights (binned on the orientation-weighted surface-area cost of
// Conty & Kulla 2018) and writes each light's trail from the root into it. One leaf (no interior
// node) for a single light; empty for none. Depth stays below 64 (the trail's bits). `offset`: how
// far off a patch the rays start (every node keeps it for the importance).
std::vector<LightTreeNode> build_light_tree(LightList& lights, const Scene& scene, float offset);

// One receiver per patch: its centroid, front normal (flipped for a back side), the radius of a
// sphere about the centroid that holds the patch grown by `offset` (the rays' offset), and the light
// the patch's triangle is.
std::vector<LightReceiver> build_light_receivers(const Scene& scene, const PatchLayout& patches,
                                                 const LightList& lights, float offset);

}  // namespace bp

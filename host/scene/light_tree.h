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
// Conty & Kulla 2018), renumbers the lights in tree order (light_of_triangle and cdf follow) and
// writes each light's trail from the root into it. A leaf is one light or one panel (a few
// coplanar triangles of one emitter); a single panel is the whole tree. Empty for no light. Depth stays below 64 (the trail's bits). `offset`: how
// far off a patch the rays start (every node keeps it for the importance).
std::vector<LightTreeNode> build_light_tree(LightList& lights, const Scene& scene, float offset);

// One receiver per patch: its centroid, front normal (flipped for a back side), the radius of a
// sphere about the centroid that holds the patch grown by `offset` (the rays' offset), the light
// the patch's triangle is, and with a BVH how much of the directional lights and the environment
// reaches it (infinite_visibility; without one, all of it).
std::vector<LightReceiver> build_light_receivers(const Scene& scene, const PatchLayout& patches,
                                                 const LightList& lights, float offset,
                                                 const FlatBvh* bvh = nullptr);

// Rays per patch and infinite light of infinite_visibility, and its floor, 1 / kVisibilityRays: a
// patch where none of them reaches the light keeps a chance as if one had.
constexpr int kVisibilityRays = 16;

}  // namespace bp

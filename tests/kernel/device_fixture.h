// Shared by the kernel tests: the first PoCL/CPU device, and a render of a Scene through exactly
// the path the CLI takes (patches, BVH, upload, PathTracerPass, render loop).
#pragma once
#include "device/device_context.h"
#include "image/image.h"
#include "device/device_scene.h"
#include "passes/ray_bundles.h"
#include "passes/render_loop.h"
#include "scene/bundle_geometry.h"
#include "scene/bvh.h"
#include "scene/patches.h"
#include "scene/scene.h"
#include <memory>

namespace bp::test {

const DeviceContext& test_device();

struct RenderRun {
  ImageRGB image;
  RenderOutcome outcome;
};

RenderRun render_pt(const Scene& scene, int width, int height, std::uint64_t spp, std::uint32_t seed,
                    std::uint32_t max_depth = 65536, bool light_sampling = true,
                    std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE);

// Everything a ray-bundle test needs, built from a Scene the way the CLI builds it.
struct BundleRig {
  Accumulator accum;
  Scene scene;
  PatchLayout patches;
  FlatBvh bvh;
  BundleGeometry geometry;
  std::unique_ptr<DeviceScene> device_scene;
  std::unique_ptr<RayBundlePass> pass;
};
std::unique_ptr<BundleRig> make_bundle_rig(const Scene& scene, float patch_size, std::uint32_t bins,
                                           std::uint32_t seed, int width = 8, int height = 8,
                                           std::uint32_t warmup = 0,
                                           std::size_t static_tiled_bytes = kStaticTiledBytes,
                                           float contact_depth_fraction = kContactDepthFraction);

// Runs `iterations` eye estimates (after the rig's warm-up) and returns the mean image.
RenderRun render_rb(BundleRig& rig, std::uint64_t iterations);

// Two parallel squares of side `side` at distance `distance`: the emitter (Le, facing +z, black)
// at z = 0, the receiver (black, facing -z) at z = distance. Material 0 emits, material 1 receives.
Scene make_parallel_squares(float side, float distance, float le);

// Closed-form form factor between two directly opposed parallel rectangles a x b at distance c.
double parallel_rectangles_form_factor(double a, double b, double c);

// The three images of a combined render (--mode combined).
struct CombinedRun {
  ImageRGB pt, rb, combined;
  RenderOutcome outcome;
  std::uint32_t pt_max_batch = 0, rb_max_batch = 0;  // the most rounds each pass sums in float before the host's doubles
};
struct CombinedSettings {
  std::uint32_t weight_mode = BP_WEIGHTS_PRODUCT;
  std::uint32_t pt_samples_per_round = 1, rb_iterations_per_round = 4;  // 0 PT samples: RB alone (--ratio 0)
  std::uint64_t rounds = 16;
  std::uint32_t seed = 1, bins = 0, warmup = 16;
  float patch_size = 0.1f;
  float cluster_size = 0.0f;  // > 0: patches clustered up to this diameter (scene/clusters.h)
  bool light_sampling = false;
  std::uint32_t beta_heuristic = BP_BETA_CLAMPED;
  float light_rate = 1.0f;  // RB's light-sample rate (light sampling)
  bool eye_direct_shared = false;  // light sampling: the eye vertex's direct light split with RB
  bool sun_own = false;            // light sampling: RB samples each directional light every iteration (--rb-sun own)
  std::uint32_t light_selection = BP_LIGHT_SELECTION_TREE;  // BP_LIGHT_SELECTION_*
};
CombinedRun render_combined(const Scene& scene, int width, int height, const CombinedSettings& settings);

// Every triangle that emits nothing split into k^2 on its barycentric grid (patch.h): the same
// surfaces, finely tessellated, for the clusters to merge back.
Scene subdivide_non_emitters(const Scene& scene, std::uint32_t k);

// A closed 1 m box seen from inside: glossy floor (kd 0.3, ks 0.5, n 30), grey Lambert walls, and a
// 0.3 m square light (Le 8) just below the ceiling, facing down.
Scene make_glossy_light_box();

// The glossy light box divided by a double-sided partition (x = 0.2, up to 0.2 m below the ceiling)
// and lit by five lights of every kind: the ceiling panel, a panel on the +x wall behind the
// partition, a small double-sided triangle hanging in the room, a point light and a spot light.
Scene make_multi_light_box();

// A closed axis-aligned box [-h,h]^3 seen from inside: 12 triangles facing inwards, one material.
Scene make_closed_box(float half_size, const SceneMaterial& material);

}  // namespace bp::test

#include "render/render_scene.h"

#include "image/video.h"
#include "scene/gltf_loader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace bp {
namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
// What a walkthrough (several frames) cannot do yet: one line each, exit 2.
void check_walkthrough_options(const RenderSpec& o) {
  if (!o.video_path.empty() && !o.views.frames())
    throw UsageError("--video encodes a walkthrough's frames: give --cameras all, --camera-path or --camera-animation");
  if (!o.video_path.empty() && !ffmpeg_on_path())
    throw UsageError("--video needs ffmpeg on PATH (Debian: apt-get install ffmpeg)");
  if (!o.views.frames()) return;
  const std::string what = "a walkthrough (--cameras all, --camera-path, --camera-animation)";
  if (!o.reference_path.empty() || !o.contact_sheet_path.empty())
    throw UsageError(std::string(!o.reference_path.empty() ? "--reference" : "--contact-sheet") +
                     " compares one image: not with " + what);
}

}  // namespace

RenderScene prepare_scene(const RenderSpec& o, const std::function<void(const std::string&)>& note) {
  using clock = std::chrono::steady_clock;
  RenderScene s;
  check_walkthrough_options(o);
  if (!o.reference_path.empty()) s.reference = read_exr(o.reference_path);

  auto t_load = clock::now();
  s.scene = load_gltf(o.scene);
  Scene& scene = s.scene;
  scene.environment = glm::vec3(o.environment[0], o.environment[1], o.environment[2]);
  if (!o.environment_path.empty()) scene.environment_image = std::make_shared<const EnvironmentImage>(load_environment_exr(o.environment_path));
  for (const std::string& w : scene.warnings)
    if (!(scene.has_environment() && w.rfind("no emitter", 0) == 0))  // the environment lights it
      note("warning: " + o.scene + ": " + w);
  if (!scene.lights.empty() && !light_sampling_applies(o))
    note("warning: " + o.scene + ": " + std::to_string(scene.lights.size()) +
         " point/spot/directional light(s) are reached by light sampling only, which this run does not use "
         "(--mode pt or --mode combined with product weights, without --no-light-sampling): they stay dark");
  s.load_seconds = seconds_since(t_load);
  try {
    s.views = select_views(scene, o.views);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }

  s.width = o.width;
  s.height = o.height;
  const float aspect = s.views.front().aspect;  // a walkthrough's frames share the first view's size
  if (s.height == 0) s.height = aspect > 0.0f ? std::max(1, int(std::lround(s.width / aspect))) : s.width;
  if (s.reference && (s.reference->width != s.width || s.reference->height != s.height))
    throw UsageError("--reference " + o.reference_path + " is " + std::to_string(s.reference->width) + "x" +
                     std::to_string(s.reference->height) + " but the render is " + std::to_string(s.width) + "x" +
                     std::to_string(s.height) + " (set --width/--height to match)");

  s.patch_size = o.patch_size > 0.0f ? o.patch_size : default_patch_size(scene);
  try {
    const float cluster_size = !o.patch_clusters ? 0.0f : o.patch_size > 0.0f ? o.patch_size : default_cluster_size(scene);
    const auto t_patches = clock::now();
    s.patches = build_patch_layout(scene, s.patch_size, cluster_size);
    s.patch_seconds = seconds_since(t_patches);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  auto t_bvh = clock::now();
  s.bvh = build_bvh(scene.triangles);
  s.bvh_seconds = seconds_since(t_bvh);
  if (o.patch_budget > 0 && !patch_refinement_applies(o))
    note(std::string("warning: --patches is --patch-refine's budget, and this render splits no patch (") +
         (o.patch_refine ? "--mode pt reads no patch's light" : "--patch-refine off") + ")");
  if (patch_refinement_applies(o)) {
    const auto t_refine = clock::now();
    try {
      LightRefinementOptions refine = light_refinement_options(scene, s.patches);
      if (o.patch_budget > 0) refine.max_patches = o.patch_budget;
      if (o.patch_budget > 0 && o.patch_budget <= s.patches.patch_count)
        note("warning: --patches " + std::to_string(o.patch_budget) + " is not above the " +
             std::to_string(s.patches.patch_count) + " patches that " +
             (o.patch_clusters ? "clusters and " : "") + "the patch size give: nothing is split "
             "(a larger --patch-size makes fewer patches)");
      s.refinement = refine_patches_by_light(scene, s.patches, s.bvh, refine);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    s.patch_seconds += seconds_since(t_refine);
  }
  return s;
}

}  // namespace bp

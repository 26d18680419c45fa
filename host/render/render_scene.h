// The scene stage of a render: the glTF loaded, the image size fixed, patches and BVH built, the
// reference image read (first: a wrong path should not cost a render).
#pragma once
#include "render/light_refinement.h"
#include "image/image.h"
#include "render/render_spec.h"
#include "scene/bvh.h"
#include "scene/patches.h"
#include "scene/scene.h"

#include <functional>
#include <optional>
#include <string>

namespace bp {

struct RenderScene {
  std::optional<ImageRGB> reference;  // --reference, sized like the render
  Scene scene;
  std::vector<SceneCamera> views;     // spec.views resolved (scene/camera_views.h); a plain render: one
  int width = 0, height = 0;          // --height 0 resolved from the camera's aspect
  float patch_size = 0.0f;            // --patch-size, or default_patch_size
  double patch_seconds = 0.0;         // the patch layout's build, clusters and refinement included
  PatchLayout patches;
  LightRefinementResult refinement;   // --patch-refine's splits (none in --mode pt)
  FlatBvh bvh;
  double load_seconds = 0.0, bvh_seconds = 0.0;
};

// Throws UsageError for a reference of another size, patches that cannot be made, views the scene
// does not have, or a walkthrough with an option it cannot take; SceneError for a camera path file
// that cannot be used; `note` gets the scene's warnings, one line each.
RenderScene prepare_scene(const RenderSpec& spec, const std::function<void(const std::string&)>& note);

}  // namespace bp

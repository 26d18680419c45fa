#include "render/render_spec.h"

namespace bp {

bool light_sampling_applies(const RenderSpec& o) {
  return o.light_sampling && (o.mode == "pt" || (o.mode == "combined" && o.weights == "product"));
}

bool patch_refinement_applies(const RenderSpec& o) { return o.patch_refine && o.mode != "pt"; }

}  // namespace bp

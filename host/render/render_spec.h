// The input of one render (the engine's RenderJob, render/render_job.h).
#pragma once
#include "scene/camera_views.h"

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace bp {

// Options that cannot make a render (a bad command line, or a render that cannot fit): the CLI
// exits 2, and the message names the option.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Everything one render is made from: scene, devices, passes, budget, outputs (the CLI fills it
// from `bundlepath render`'s options, cli/options.cpp).
struct RenderSpec {
  std::string scene;
  std::string out_prefix;        // default: out/<scene file stem>
  int width = 512;
  int height = 0;                // 0: from the width and the camera's aspect ratio (square if none)
  std::uint64_t spp = 0;         // --mode pt/combined; 0 and no time: 64
  std::uint64_t iterations = 0;  // --mode rb/combined; 0 and no time: 1000 (rb)
  // --mode combined --ratio auto with no budget: render as long as --mode pt's this many samples per
  // pixel would take, at the probe's costs (passes/combined.h, equal_time_rounds); 0: a budget is given.
  std::uint64_t equal_time_spp = 0;
  std::uint32_t bins = 0;        // 0: chosen from the patch count
  std::uint32_t warmup = 16;     // ray-bundle iterations before the first eye estimate
  float contact_depth = -1.0f;   // --contact-depth: touching surfaces' depth, a fraction of the scene; < 0: kContactDepthFraction
  bool gouraud = true;           // --rb-shading gouraud|flat
  bool eye_blocks = true;        // --rb-eye-gather blocks|every
  std::string rb_directions = "independent";  // --rb-directions stratified|independent (passes/bundle_directions.h)
  double seconds = 0.0;
  double target_error = 0.0;     // --target-error: stop once the estimated relMSE is at most this; 0: none
  std::uint64_t error_batch = 0;  // RB iterations per batch of the error estimate; 0: kErrorBatchRbIterations
  int error_levels = 1;          // batch lengths error_batch · 2^j, j < error_levels, in the stats (blocking)
  std::uint32_t seed = 1;
  std::string device;            // --device: indices or names, comma-separated, or all; empty: first GPU, else first CPU
  std::string mode = "combined";  // pt, rb, combined
  std::string weights = "product";  // combined: product, paper, none
  std::string beta = "clamped";     // product weights: the per-vertex beta, clamped or balance
  float light_rate = 0.0f;          // combined + light sampling: RB's light-sample rate; 0: default_light_rate
  std::string eye_direct = "auto";  // combined + light sampling: the eye vertex's direct light, shared, pt or auto
  bool rb_sun_own = false;          // combined + light sampling: --rb-sun own (RB samples each sun every iteration)
  double ratio = -1.0;           // combined: PT samples per pixel per RB iteration (0: RB alone); < 0: auto
  std::string rb_level = "consistent";  // combined, product weights: RB's share: consistent, regional, corrected or own
  int regions = 8;               // --regions N: the N x N grid of the regional error and --rb-level regional
  double target_block_error = 0.0;  // --target-block-error: stop once the expected worst region's error is at most this
  bool all_layers = false;       // --layers all: also pt_raw and rb_raw
  bool denoise = false;          // --denoise: OpenImageDenoise on the image (raw.* kept), inside --time
  bool light_sampling = true;    // --no-light-sampling turns it off (light_sampling_applies says where it acts)
  std::string light_selection = "tree";  // light sampling's choice of light: tree (per receiving patch) or power
  bool generic_kernels = false;  // --kernels generic: every feature compiled in (for comparison)
  std::string reference_path;    // --reference REF.exr
  std::string contact_sheet_path;
  std::string checkpoint_path;   // --checkpoint FILE: written every checkpoint_every seconds and at the end
  double checkpoint_every = 60.0;
  double save_every = 0.0;       // --save-every S: the image files written every S seconds of the rounds (0: at the end)
  std::string resume_path;       // --resume FILE: continue a checkpointed render
  float patch_size = 0.0f;       // metres; 0: derived from the scene's extent
  bool patch_clusters = true;    // --patch-clusters: merge flat triangles into clusters (scene/clusters.h)
  bool patch_refine = true;      // --patch-refine: split patches where the direct light's shadows cross them
  std::uint64_t patch_budget = 0;  // --patches: the most patches refinement may reach; 0: kPatchBudgetFactor x unrefined
  std::string stats_path;
  float exposure = 0.0f;         // PNG exposure in stops
  std::array<float, 3> environment{0.0f, 0.0f, 0.0f};  // --environment R,G,B: uniform radiance, W sr^-1 m^-2
  std::string environment_path;  // --environment FILE.exr: an equirectangular radiance map (wins over R,G,B)
  std::uint32_t max_depth = 65536;
  // The views (walkthroughs, docs/design.md §8): --camera, --cameras all, --camera-path, --camera-animation,
  // --fps. A walkthrough writes PREFIX_0000.exr, PREFIX_0000.png, ... (render_outputs.h).
  ViewRequest views;
  std::string video_path;  // --video FILE.mp4: a walkthrough's PNGs encoded by ffmpeg
};

// Whether light sampling (docs/design.md §3) is part of this render: asked for, and a mode that has it
// (--mode pt; --mode combined with product weights). RB alone, the paper's weights and the plain
// sum keep the paper's two estimators.
bool light_sampling_applies(const RenderSpec& o);

// Whether --patch-refine splits patches in this render: asked for, and a mode with ray bundles (the
// path tracer alone reads no patch's light).
bool patch_refinement_applies(const RenderSpec& o);

// --rb-level corrected or regional (image/rb_level.h): --mode combined with product weights, whose PT
// samples also estimate RB's share (PT's unweighted less its weighted image); --ratio 0 has no PT to ask.
inline bool rb_level_corrected(const RenderSpec& o) {
  return o.mode == "combined" && o.weights == "product" && o.rb_level != "own" && o.ratio != 0.0;
}
// The grid --rb-level's factors are per region of: regional, N x N; corrected, one for the image.
inline int rb_level_regions(const RenderSpec& o) { return o.rb_level == "corrected" ? 1 : o.regions; }
// --rb-level consistent (image/share_correction.h): the regional level, then PT's estimate of RB's
// share corrects it block by block down to each pixel.
inline bool rb_share_consistent(const RenderSpec& o) { return rb_level_corrected(o) && o.rb_level == "consistent"; }

// --ratio auto (the default of --mode combined): a timed probe before the render picks c.
inline bool ratio_is_auto(const RenderSpec& o) { return o.mode == "combined" && o.ratio < 0.0; }

}  // namespace bp

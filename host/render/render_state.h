// The objects of one render, shared by the engine's stages (render_job.cpp builds and runs them;
// render_outputs.cpp and render_stats.cpp read them). Internal to host/render/.
#pragma once
#include "image/accumulator.h"
#include "image/denoiser.h"
#include "image/error_estimate.h"
#include "image/rb_level.h"
#include "image/regional_error.h"
#include "passes/checkpoint.h"
#include "passes/combined.h"
#include "passes/each_view.h"
#include "passes/path_tracer.h"
#include "passes/ray_bundles.h"
#include "passes/render_loop.h"
#include "render/parallel_pass.h"
#include "render/rank_pass.h"
#include "render/ranks.h"
#include "render/render_devices.h"
#include "render/render_job.h"
#include "render/render_scene.h"
#include "scene/bundle_geometry.h"

#include <cstdio>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bp {

// One view of the render: a plain render has one, a walkthrough one per frame (docs/design.md §8). Its
// accumulators are what checkpoints, its error estimate and its image files read.
struct RenderView {
  SceneCamera scene_camera;
  CameraParams camera{};
  Accumulator pt_accum, rb_accum;
  std::optional<ImageErrorEstimate> error_estimate;
  double estimated_rel_mse = NAN;
  std::optional<RbLevel> rb_level;  // --rb-level corrected or regional: RB's layer level from both estimators
  std::optional<RegionalError> regional_error;  // each region's error (image/regional_error.h)
  double expected_worst_region_error = NAN;     // its expected largest relative error
  std::string out_prefix;  // --out, or PREFIX_0000, PREFIX_0001, ... for a walkthrough's frames
  // --rb-level consistent: PT's unweighted image u and its estimate of RB's share d = u − w, in
  // batches of one round (image/share_correction.h needs d's variance, the error estimate u's too).
  std::optional<BatchMeansErrorEstimate> pt_raw_batches, pt_share_batches;
  FirstHitFeatures features;     // the albedo and normal layers (passes/path_tracer.h)
  FirstHitFeatures prefiltered;  // --denoise: the same denoised alone, as the beauty's filter reads them
};

struct RenderState {
  RenderState(const RenderSpec& s, const Ranks& r) : spec(s), ranks(r) {}
  const RenderSpec& spec;
  const Ranks& ranks;  // the processes rendering this image (render/rank_pass.h)
  RenderScene scene;

  std::vector<std::unique_ptr<RenderDevice>> devices;
  DeviceRoles roles;
  bool use_pt = false, use_rb = false;
  std::optional<RoundShape> shape;  // --mode combined's round
  std::uint32_t weight_mode = 0;
  float ratio_n2_over_n1 = 1.0f;
  bool light_sampling = false;
  float light_rate = 1.0f;
  std::string kernel_options;
  bool eye_direct_shared = false;

  // The render's views (a deque: passes and round sums hold pointers into them). Checkpoints, several
  // devices, several ranks and --reference take one view (a walkthrough refuses them, render_scene.cpp).
  std::deque<RenderView> views;
  // Several ranks: this rank's sums of each batch, added into root's view accumulators after it
  // (render/rank_pass.h).
  Accumulator pt_rank_batch, rb_rank_batch;
  // Several devices: each pass adds into an accumulator of its own, merged into the rank's after
  // every batch (render/parallel_pass.h).
  std::deque<Accumulator> lane_accums;
  std::vector<Accumulator*> pt_pass_accums;  // what each PT pass adds into
  Accumulator* rb_pass_accum = nullptr;      // what the ray-bundle pass adds into
  PathTracerSettings pt_settings;
  // One per PT device (roles.pt), in that order; a walkthrough (one device): one per view.
  std::vector<std::unique_ptr<PathTracerPass>> pt;
  std::unique_ptr<RayBundlePass> rb;
  std::optional<BundleGeometry> geometry;
  RayBundleSettings rb_settings;
  std::optional<RatioProbe> probe;

  std::unique_ptr<Denoiser> denoiser;  // --denoise
  double denoise_seconds = 0.0;        // the features, their prefilter and the beauty's denoise (root)
  double reserved_seconds = 0.0;       // of --time, kept for what comes after the rounds (--denoise)
  double beauty_denoise_seconds = 0.0; // the beauty's denoise, estimated from the prefilter (--denoise)

  std::optional<Checkpoint> resumed;
  std::uint64_t first_round = 0;
  double earlier_seconds = 0.0;
  std::string key;  // the checkpoint key

  double estimated_rel_mse = NAN;  // the worst view's
  double expected_worst_region_error = NAN;  // the worst view's (image/regional_error.h)

  std::unique_ptr<ProgressivePass> each_view_pt;  // a walkthrough's path tracers, one per view
  std::unique_ptr<ProgressivePass> schedule;  // the combination or the devices' lanes, when there is one
  ParallelPass* lanes = nullptr;              // the schedule, on several devices
  std::unique_ptr<RankPass> rank_schedule;    // the schedule's slices on this rank, on several ranks
  ProgressivePass* pass = nullptr;            // what the render loop runs
  std::uint64_t rounds = 0;                   // the round target (0: none)
  RenderOutcome outcome;

  RenderDevice& pt_device(std::size_t k = 0) { return *devices[roles.pt[k]]; }
  RenderDevice& rb_device() { return *devices[roles.rb]; }
  bool several_devices() const { return devices.size() > 1; }
  bool several_ranks() const { return ranks.size() > 1; }
  RenderView& first_view() { return views.front(); }
  const RenderView& first_view() const { return views.front(); }
  bool walkthrough() const { return spec.views.frames(); }
  // Whether RB renders anything: it has a pass, and --ratio auto did not choose the path tracer alone.
  bool rb_renders() const { return rb && !(shape && shape->pt_alone()); }
  // Where this rank's passes end a batch: the (one) view's accumulators on one rank.
  Accumulator& pt_rank_accum() { return several_ranks() ? pt_rank_batch : first_view().pt_accum; }
  Accumulator& rb_rank_accum() { return several_ranks() ? rb_rank_batch : first_view().rb_accum; }
};

// printf into a std::string, for the observer's notes.
template <class... Args>
std::string printf_text(const char* format, Args... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, args...);
  return buf;
}

}  // namespace bp

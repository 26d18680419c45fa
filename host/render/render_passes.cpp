// The passes of a render on their devices, and the choices --ratio auto and --eye-direct auto make.
#include "render/render_passes.h"

#include "device/kernel_features.h"
#include "render/checkpoint_key.h"
#include "render/parallel_pass.h"

#include <unistd.h>

namespace bp {
namespace {

std::uint32_t weight_mode_of(const RenderSpec& o) {
  if (o.mode != "combined" || o.weights == "none") return BP_WEIGHTS_NONE;
  return o.weights == "paper" ? BP_WEIGHTS_PAPER : BP_WEIGHTS_PRODUCT;
}

std::uint32_t beta_heuristic_of(const RenderSpec& o) {
  return o.beta == "balance" ? BP_BETA_BALANCE : BP_BETA_CLAMPED;
}

std::string ratio_text(const RoundShape& shape) {
  if (shape.pt_alone()) return "inf (the path tracer alone)";
  return shape.rb_iterations == 1 ? std::to_string(shape.pt_samples) : "1/" + std::to_string(shape.rb_iterations);
}

}  // namespace

// The round shape and the weights both passes use; --ratio 0 (no PT samples) runs RB unweighted.
void choose_round(RenderState& s) {
  const RenderSpec& o = s.spec;
  s.use_pt = o.mode != "rb";
  s.use_rb = o.mode != "pt";
  if (o.mode == "combined") {
    try {
      s.shape = round_shape(ratio_is_auto(o) ? 0.25 : o.ratio);  // auto: replaced by the probe's choice
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  const CombinedWeights weights = s.shape ? combined_weights(weight_mode_of(o), *s.shape) : CombinedWeights{};
  s.weight_mode = weights.mode;
  s.ratio_n2_over_n1 = weights.ratio_n2_over_n1;
}

// The devices --device names, each with the scene; the light tree's receivers must fit each of them.
void open_devices(RenderState& s) {
  const RenderSpec& o = s.spec;
  const std::vector<DeviceInfo> infos = select_devices(o.device);
  if (infos.size() > 1 && s.walkthrough())
    throw UsageError("a walkthrough renders on one device: --device names " + std::to_string(infos.size()));
  if (s.several_ranks() && s.walkthrough())
    throw UsageError("a walkthrough renders in one process: run it without mpirun (" +
                     std::to_string(s.ranks.size()) + " ranks)");
  s.roles = assign_device_roles(o.mode, infos.size());
  // The light tree and its per-patch receivers only where light sampling acts (power needs neither).
  const bool light_tree = light_sampling_applies(o) && o.light_selection == "tree";
  // One receiver per patch: refused before anything is built when it cannot fit a device.
  const std::size_t receiver_bytes = light_tree ? s.scene.patches.patch_count * sizeof(LightReceiver) : 0;
  for (const DeviceInfo& info : infos)
    if (receiver_bytes > info.max_alloc_bytes || receiver_bytes > info.global_memory_bytes / 4)
      throw UsageError("the light tree needs " + std::to_string(receiver_bytes >> 20) + " MiB for its " +
                       std::to_string(s.scene.patches.patch_count) + " receiving patches, more than " +
                       info.device_name + " offers (at most " + std::to_string(info.max_alloc_bytes >> 20) +
                       " MiB per buffer): raise --patch-size or use --light-selection power");
  // All textures' texels are one buffer: refused before anything is built when it cannot fit a device.
  const std::size_t texel_bytes = s.scene.scene.has_textures() ? s.scene.scene.texels.size() * sizeof(std::uint32_t) : 0;
  for (const DeviceInfo& info : infos)
    if (texel_bytes > info.max_alloc_bytes || texel_bytes > info.global_memory_bytes / 4)
      throw UsageError("the scene's textures need " + std::to_string(texel_bytes >> 20) + " MiB, more than " +
                       info.device_name + " offers (at most " + std::to_string(info.max_alloc_bytes >> 20) +
                       " MiB per buffer)");
  for (const DeviceInfo& info : infos)
    s.devices.push_back(std::make_unique<RenderDevice>(info, s.scene,
                                                       light_tree ? BP_LIGHT_SELECTION_TREE : BP_LIGHT_SELECTION_POWER));
}

// Where a pass adds its estimates: the rank's accumulator on one device (the render's on one rank),
// its own on several.
static Accumulator& pass_accumulator(RenderState& s, Accumulator& rank_accum) {
  if (!s.several_devices()) return rank_accum;
  return s.lane_accums.emplace_back(rank_accum.width, rank_accum.height, rank_accum.keeps_raw());
}

// One chain for every view (docs/design.md §8): each view adds its own eye gather per iteration. On several
// devices or ranks (one view) the pass adds into s.rb_pass_accum.
static void build_rb_pass(RenderState& s) {
  std::vector<RayBundleView> views;
  for (RenderView& view : s.views)
    views.push_back(RayBundleView{view.camera, s.rb_pass_accum ? s.rb_pass_accum : &view.rb_accum});
  try {  // more fragment slots than it can address: a run that does not fit, as check_bundle_memory's
    s.rb = std::make_unique<RayBundlePass>(s.rb_device().context, s.rb_device().scene, *s.geometry, views, s.rb_settings);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

// Whether PT keeps its unweighted sums: for --layers all, and for the corrected RB level.
static bool pt_keeps_raw(const RenderSpec& o) { return o.all_layers || rb_level_corrected(o); }

// The views' cameras, accumulators and output prefixes: a walkthrough's frames are PREFIX_0000, ...
static void build_views(RenderState& s) {
  const RenderSpec& o = s.spec;
  const int width = s.scene.width, height = s.scene.height;
  for (std::size_t k = 0; k < s.scene.views.size(); ++k) {
    RenderView& view = s.views.emplace_back();
    view.scene_camera = s.scene.views[k];
    view.camera = pack_camera(view.scene_camera, width, height);
    // PT's unweighted sums also give the corrected RB level (image/rb_level.h).
    view.pt_accum = Accumulator(width, height, pt_keeps_raw(o));
    view.rb_accum = Accumulator(width, height, o.all_layers);
    view.out_prefix = s.walkthrough() ? printf_text("%s_%04zu", o.out_prefix.c_str(), k) : o.out_prefix;
  }
}

// A pass per PT device; a walkthrough (one device) a pass per view.
static void build_pt_passes(RenderState& s) {
  if (s.walkthrough()) {
    for (RenderView& view : s.views)
      s.pt.push_back(std::make_unique<PathTracerPass>(s.pt_device().context, s.pt_device().scene, view.camera,
                                                      s.pt_settings, view.pt_accum));
    return;
  }
  for (std::size_t k = 0; k < s.roles.pt.size(); ++k) {
    s.pt_pass_accums.push_back(&pass_accumulator(s, s.pt_rank_accum()));
    s.pt.push_back(std::make_unique<PathTracerPass>(s.pt_device(k).context, s.pt_device(k).scene,
                                                    s.first_view().camera, s.pt_settings, *s.pt_pass_accums.back()));
  }
}

// What grows with the views: per view the path tracer's pixel sums and RB's eye hits and sums on the
// device, and the accumulators and error estimate on the host. Refused naming the size and the views.
static void check_view_memory(const RenderState& s, std::size_t rb_device_bytes) {
  const RenderSpec& o = s.spec;
  const std::size_t views = s.scene.views.size(), pixels = std::size_t(s.scene.width) * s.scene.height;
  const DeviceInfo& device = s.devices.front()->context.info;
  const std::size_t device_bytes = rb_device_bytes + (s.use_pt ? views * pixels * sizeof(PixelAccum) : 0);
  // Host: per view the pt and rb sums (raw too with --layers all), the error estimate's two sums per
  // level and estimator (image/error_estimate.h) and the layers written at the end (floats), all RGB.
  const std::size_t estimators = std::size_t(s.use_pt) + std::size_t(s.use_rb);
  const std::size_t host_bytes =
      views * pixels * 3 *
      (sizeof(double) * (2 * (o.all_layers ? 2 : 1) + 2 * std::size_t(o.error_levels) * estimators) + 4 * 4);
  const std::size_t host_memory = std::size_t(sysconf(_SC_PHYS_PAGES)) * std::size_t(sysconf(_SC_PAGE_SIZE));
  const bool device_short = device_bytes > device.global_memory_bytes / 4 * 3;
  if (device_short || host_bytes > host_memory / 2)
    throw UsageError(printf_text("%zu view(s) of %dx%d need about %zu MiB of %s memory, more than %s offers (%zu MiB): "
                                 "lower --width/--height or the number of views",
                                 views, s.scene.width, s.scene.height, (device_short ? device_bytes : host_bytes) >> 20,
                                 device_short ? "device" : "host",
                                 device_short ? device.device_name.c_str() : "this machine",
                                 std::size_t(device_short ? device.global_memory_bytes : host_memory) >> 20));
}

void build_passes(RenderState& s) {
  const RenderSpec& o = s.spec;
  const Scene& scene = s.scene.scene;
  const DeviceScene& first_scene = s.devices.front()->scene;
  const int width = s.scene.width, height = s.scene.height;
  s.light_sampling = light_sampling_applies(o) && first_scene.light_count > 0;
  s.light_rate = o.light_rate > 0.0f ? o.light_rate
                                     : default_light_rate(s.scene.patches.patch_count, std::size_t(width) * height);
  s.kernel_options = o.generic_kernels ? "" : kernel_options(features_for(scene, s.light_sampling));
  // Both passes or neither: the split is exact only when PT and RB weight the eye vertex alike.
  // --eye-direct auto builds them shared (RB's chains are a superset) and decides later.
  const bool eye_direct_auto = s.light_sampling && s.use_pt && s.use_rb && o.eye_direct == "auto";
  s.eye_direct_shared = s.light_sampling && (o.eye_direct == "shared" || eye_direct_auto);

  if (s.use_pt) {
    PathTracerSettings& settings = s.pt_settings;
    settings.seed = o.seed;
    settings.max_depth = o.max_depth;
    settings.weight_mode = s.weight_mode;
    settings.weight_ratio = s.ratio_n2_over_n1;
    settings.beta_heuristic = beta_heuristic_of(o);
    settings.rb_light_rate = s.light_rate;
    settings.rb_sun_own = s.light_sampling && s.use_rb && o.rb_sun_own;
    settings.light_sampling = s.light_sampling;
    settings.eye_direct_shared = s.eye_direct_shared;
    settings.kernel_options = s.kernel_options;
  }
  std::size_t rb_device_bytes = 0;
  if (s.use_rb) {
    const BundleSize size = bundle_size(scene, s.scene.patches);
    RayBundleSettings& rb = s.rb_settings;
    rb.seed = rank_chain_seed(o.seed, s.ranks.rank());  // a chain of its own on each rank
    // --patch-refine's patches are local: the buffer keeps the bins of the layout before it
    const LightRefinementResult& refined = s.scene.refinement;
    const double unrefined_share = refined.patches_before > 0 ? double(refined.patches_before) / s.scene.patches.patch_count : 1.0;
    rb.bins = o.bins ? o.bins : default_bins(size, kDefaultBinsPerElement * unrefined_share);
    if (o.contact_depth >= 0.0f) rb.contact_depth_fraction = o.contact_depth;
    rb.warmup = o.warmup;
    rb.directions = o.rb_directions == "independent" ? DirectionSequence::independent : DirectionSequence::stratified;
    rb.gouraud = o.gouraud;
    rb.light_sampling = s.light_sampling;
    rb.eye_direct_shared = s.eye_direct_shared;
    rb.kernel_options = s.kernel_options;
    rb.weight_mode = s.weight_mode;
    rb.weight_ratio = s.ratio_n2_over_n1;
    rb.beta_heuristic = beta_heuristic_of(o);
    rb.light_rate = s.light_rate;
    rb.sun_own = s.light_sampling && o.rb_sun_own;
    rb.keep_raw = o.all_layers;
    rb.eye_blocks = o.eye_blocks;
    rb.glossy = features_for(scene, s.light_sampling).glossy();
    try {
      check_bundle_memory(s.rb_device().context.info, size, rb.bins, std::size_t(width) * height, bundle_chains(rb),
                          scene.has_shading_normals(), scene.has_textures());
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    // A walkthrough's views each have their eye hits and sums: checked with the views below.
    rb_device_bytes = estimate_bundle_memory(size, rb.bins, std::size_t(width) * height * s.scene.views.size(),
                                             bundle_chains(rb), scene.has_shading_normals(), scene.has_textures());
  }
  if (s.scene.views.size() > 1) check_view_memory(s, rb_device_bytes);
  build_views(s);
  if (s.several_ranks()) {  // one view (a walkthrough refuses ranks, open_devices)
    s.pt_rank_batch = Accumulator(width, height, pt_keeps_raw(o));
    s.rb_rank_batch = Accumulator(width, height, o.all_layers);
  }
  if (s.use_pt) build_pt_passes(s);
  if (s.use_rb) {
    s.geometry = build_bundle_geometry(scene, s.scene.patches);
    // Several devices or ranks: the pass adds into an accumulator of its own (one view).
    if (s.several_devices() || s.several_ranks()) s.rb_pass_accum = &pass_accumulator(s, s.rb_rank_accum());
    build_rb_pass(s);
  }
}

// PT timed on a pass of its own at a smaller size of the same view (passes/combined.h), on the first
// PT device; RB on its own pass.
static RatioProbe run_probe(RenderState& s, double pt_time_share) {
  const RenderSpec& o = s.spec;
  const ProbeImageSize size = probe_image_size(s.scene.width, s.scene.height);
  Accumulator probe_accum(size.width, size.height, true);  // unweighted sums too: κ
  PathTracerPass probe_pt(s.pt_device().context, s.pt_device().scene,
                          pack_camera(s.first_view().scene_camera, size.width, size.height), s.pt_settings, probe_accum);
  std::vector<Accumulator*> rb_accums;
  for (RenderView& view : s.views) rb_accums.push_back(s.several_devices() ? s.rb_pass_accum : &view.rb_accum);
  // A walkthrough's round has every view's PT samples: the pixels of all views (the views' PT costs
  // per pixel taken as the first's).
  return probe_ratio(probe_pt, probe_accum, std::size_t(s.scene.width) * s.scene.height * s.views.size(), *s.rb,
                     rb_accums,
                     RatioProbeBudget{o.seconds, o.spp, o.iterations, pt_time_share, o.equal_time_spp, s.weight_mode});
}

// The probe's round: its time share's on one device; on several, where PT and RB run at the same
// time, the round that keeps both busy (PT's time per sample shared by its devices).
static void choose_probed_shape(RenderState& s) {
  if (s.several_devices())
    s.probe->chosen = concurrent_ratio_shape(s.probe->pt_seconds_per_spp / double(s.pt.size()),
                                             s.probe->rb_seconds_per_iteration);
  s.shape = s.probe->chosen;
}

// Whether --eye-direct auto has a choice to make: both estimators, with product weights.
static bool eye_direct_is_auto(const RenderState& s) {
  const bool eye_direct_auto = s.light_sampling && s.use_pt && s.use_rb && s.spec.eye_direct == "auto";
  return eye_direct_auto && !s.pt.empty() && s.rb && s.weight_mode == BP_WEIGHTS_PRODUCT;
}

// PT's time share where the eye vertex's direct light is its alone, at least the probe's glossy share.
static double pt_alone_share(const RenderState& s) {
  return probed_pt_time_share(auto_ratio_pt_time_share(true), s.probe ? s.probe->pt_variance_kept : std::nan(""));
}

// --ratio auto: the probe picks c (or a resumed render takes the checkpoint's); --eye-direct auto:
// pt where point, spot and sun lights hold kEyeDirectPtFromDeltaLightShare of the light, else shared
// below kEyeDirectSharedBelowSpp PT samples per pixel, or what a resumed render was saved with.
// Sets s.shape and s.eye_direct_shared; the passes are not changed yet.
static void decide_auto_settings(RenderState& s, RenderObserver& observer) {
  const RenderSpec& o = s.spec;
  if (ratio_is_auto(o)) {
    if (s.resumed) {
      if (std::optional<RoundShape> saved = round_of_key(s.resumed->options)) s.shape = *saved;
      if (s.shape->pt_alone() && o.iterations)
        throw UsageError("the checkpoint was rendered by the path tracer alone (--ratio auto chose it): count "
                         "with --spp or --time, not --iterations");
    } else if (o.denoise) {
      // Under a denoiser the path tracer's white noise is what OIDN removes and the ray bundles'
      // low-frequency error is what it keeps: the path tracer alone, no probe (docs/results.md,
      // "Denoised images": on the Lambert house at 30 s half the default's error after denoising).
      s.shape = RoundShape{1, 0};
      observer.note("--ratio auto with --denoise: the path tracer alone (a denoiser removes its noise, not the ray "
                    "bundles' smooth error; give --ratio to combine)");
    } else {
      // The share for the eye-direct choice known now (auto counts as shared until it is resolved).
      s.probe = run_probe(s, auto_ratio_pt_time_share(s.light_sampling && !s.eye_direct_shared));
      choose_probed_shape(s);
    }
  }
  if (eye_direct_is_auto(s)) {
    std::optional<bool> saved = s.resumed ? eye_direct_shared_of_key(s.resumed->options) : std::nullopt;
    if (saved) {
      s.eye_direct_shared = *saved;
    } else if (s.shape->pt_alone()) {
      s.eye_direct_shared = false;  // RB renders nothing
    } else if (const float sharp = s.devices.front()->scene.delta_light_share;
               sharp >= kEyeDirectPtFromDeltaLightShare) {
      s.eye_direct_shared = false;
      observer.note(printf_text("--eye-direct auto: pt (point, spot and sun lights hold %.0f %% of the light: their "
                                "sharp shadows are the path tracer's)",
                                100.0 * sharp));
    } else {
      // A --time budget needs the probe's costs: probed here when --ratio did not probe already.
      double t_pt = s.probe ? s.probe->pt_seconds_per_spp : 0.0, t_rb = s.probe ? s.probe->rb_seconds_per_iteration : 0.0;
      if (!s.probe && o.seconds > 0.0 && !o.spp && !o.iterations) {
        const RatioProbe timing = run_probe(s, kAutoRatioPtTimeShareEyeShared);
        t_pt = timing.pt_seconds_per_spp;
        t_rb = timing.rb_seconds_per_iteration;
      }
      // N ranks render N times one rank's rounds in a --time (each rank with a machine of its own).
      const double seconds = o.seconds * double(s.ranks.size());
      // Under --ratio auto, the samples PT would get with the eye vertex's direct light its own: at
      // that choice's share, not at the smaller shared one (which would tip every short render to shared).
      const bool at_pt_share = ratio_is_auto(o) && !s.several_devices();
      const RoundShape shape =
          at_pt_share ? auto_ratio_shape(t_pt, t_rb, pt_alone_share(s), s.probe ? s.probe->bounds : AutoRatioBounds{})
                      : *s.shape;
      const double spp = expected_pt_spp(shape, o.spp, o.iterations, seconds, t_pt, t_rb);
      s.eye_direct_shared = spp < kEyeDirectSharedBelowSpp;
      observer.note(printf_text("--eye-direct auto: %s (about %.0f PT samples per pixel%s)",
                                s.eye_direct_shared ? "shared" : "pt", spp, at_pt_share ? " at pt's ratio" : ""));
    }
    if (!s.eye_direct_shared && s.probe) {  // PT's alone: the ratio for that share (pt_alone_share)
      s.probe->pt_time_share = pt_alone_share(s);
      s.probe->chosen = auto_ratio_shape(s.probe->pt_seconds_per_spp, s.probe->rb_seconds_per_iteration,
                                         s.probe->pt_time_share, s.probe->bounds);
      choose_probed_shape(s);
    }
  }
  if (s.probe && s.several_devices())
    observer.note(printf_text("--ratio auto: c = %s (PT %.4g s per sample per pixel over %zu device(s), RB %.4g s per "
                              "iteration, at the same time: the round that keeps both busy; probe %.2f s)",
                              ratio_text(*s.shape).c_str(), s.probe->pt_seconds_per_spp / double(s.pt.size()),
                              s.pt.size(), s.probe->rb_seconds_per_iteration, s.probe->probe_seconds));
  else if (s.probe)
    observer.note(printf_text("--ratio auto: c = %s (PT %.4g s per sample per pixel, RB %.4g s per iteration, PT "
                              "time share %.2f, PT's weights keep %.3g of its variance; probe %.2f s)",
                              ratio_text(*s.shape).c_str(), s.probe->pt_seconds_per_spp,
                              s.probe->rb_seconds_per_iteration, s.probe->pt_time_share,
                              s.probe->pt_variance_kept, s.probe->probe_seconds));
}

// Both passes get the chosen c's weights before the first counted sample. On several ranks root's
// probe decides, and every rank renders with its choices (the weights hold only if c is the same).
void choose_auto_settings(RenderState& s, RenderObserver& observer) {
  if (s.ranks.root()) decide_auto_settings(s, observer);
  if (s.shape) s.ranks.broadcast(*s.shape);
  s.ranks.broadcast(s.eye_direct_shared);
  // Where it is pt, the ray-bundle pass is made again without the eye chain (unless it renders nothing).
  if (eye_direct_is_auto(s) && !s.eye_direct_shared) {
    for (auto& pt : s.pt) pt->set_eye_direct_shared(false);
    s.rb_settings.eye_direct_shared = false;
    if (!s.shape->pt_alone()) build_rb_pass(s);
  }
  if (ratio_is_auto(s.spec)) {  // PT alone: PT unweighted (combined_weights), RB never runs
    const CombinedWeights weights = combined_weights(s.weight_mode, *s.shape);
    s.ratio_n2_over_n1 = weights.ratio_n2_over_n1;
    for (auto& pt : s.pt) pt->set_weights(weights.mode, weights.ratio_n2_over_n1);
    s.rb->set_weight_ratio(weights.ratio_n2_over_n1);
  }
}

}  // namespace bp

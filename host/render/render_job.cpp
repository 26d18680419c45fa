// The stages of a render: scene -> devices -> passes -> (probe) -> resume -> rounds -> outputs.
#include "render/render_job.h"

#include "device/kernel_features.h"
#include "render/checkpoint_key.h"
#include "render/render_outputs.h"
#include "render/render_state.h"
#include "render/render_stats.h"

#include <cmath>
#include <cstdio>

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
  return shape.rb_iterations == 1 ? std::to_string(shape.pt_samples) : "1/" + std::to_string(shape.rb_iterations);
}

std::string printf_text(const char* format, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, args...);
  return buf;
}

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
  for (const DeviceInfo& info : infos)
    s.devices.push_back(std::make_unique<RenderDevice>(info, s.scene,
                                                       light_tree ? BP_LIGHT_SELECTION_TREE : BP_LIGHT_SELECTION_POWER));
}

// Where a pass adds its estimates: the render's accumulator on one device, its own on several.
Accumulator& pass_accumulator(RenderState& s, Accumulator& render_accum) {
  if (!s.several_devices()) return render_accum;
  return s.lane_accums.emplace_back(render_accum.width, render_accum.height, render_accum.keeps_raw());
}

void build_rb_pass(RenderState& s, Accumulator& accum) {
  s.rb = std::make_unique<RayBundlePass>(s.rb_device().context, s.rb_device().scene, *s.geometry, s.camera,
                                         s.rb_settings, accum);
}

void build_passes(RenderState& s) {
  const RenderSpec& o = s.spec;
  const Scene& scene = s.scene.scene;
  const DeviceScene& first_scene = s.devices.front()->scene;
  const int width = s.scene.width, height = s.scene.height;
  s.camera = pack_camera(scene.camera, width, height);
  s.light_sampling = light_sampling_applies(o) && first_scene.light_count > 0;
  s.light_rate = o.light_rate > 0.0f ? o.light_rate
                                     : default_light_rate(s.scene.patches.patch_count, std::size_t(width) * height);
  s.kernel_options = o.generic_kernels ? "" : kernel_options(features_for(scene, s.light_sampling));
  // Both passes or neither: the split is exact only when PT and RB weight the eye vertex alike.
  // --eye-direct auto builds them shared (RB's chains are a superset) and decides later.
  const bool eye_direct_auto = s.light_sampling && s.use_pt && s.use_rb && o.eye_direct == "auto";
  s.eye_direct_shared = s.light_sampling && (o.eye_direct == "shared" || eye_direct_auto);
  s.pt_accum = Accumulator(width, height, o.all_layers);
  s.rb_accum = Accumulator(width, height, o.all_layers);

  if (s.use_pt) {
    PathTracerSettings& settings = s.pt_settings;
    settings.seed = o.seed;
    settings.max_depth = o.max_depth;
    settings.weight_mode = s.weight_mode;
    settings.weight_ratio = s.ratio_n2_over_n1;
    settings.beta_heuristic = beta_heuristic_of(o);
    settings.rb_light_rate = s.light_rate;
    settings.light_sampling = s.light_sampling;
    settings.eye_direct_shared = s.eye_direct_shared;
    settings.kernel_options = s.kernel_options;
    for (std::size_t k = 0; k < s.roles.pt.size(); ++k) {
      s.pt_pass_accums.push_back(&pass_accumulator(s, s.pt_accum));
      s.pt.push_back(std::make_unique<PathTracerPass>(s.pt_device(k).context, s.pt_device(k).scene, s.camera,
                                                      settings, *s.pt_pass_accums.back()));
    }
  }
  if (s.use_rb) {
    const BundleSize size = bundle_size(scene, s.scene.patches);
    RayBundleSettings& rb = s.rb_settings;
    rb.seed = o.seed;
    rb.bins = o.bins ? o.bins : default_bins(size);
    if (o.contact_depth >= 0.0f) rb.contact_depth_fraction = o.contact_depth;
    rb.warmup = o.warmup;
    rb.gouraud = o.gouraud;
    rb.light_sampling = s.light_sampling;
    rb.eye_direct_shared = s.eye_direct_shared;
    rb.kernel_options = s.kernel_options;
    rb.weight_mode = s.weight_mode;
    rb.weight_ratio = s.ratio_n2_over_n1;
    rb.beta_heuristic = beta_heuristic_of(o);
    rb.light_rate = s.light_rate;
    rb.keep_raw = o.all_layers;
    try {
      check_bundle_memory(s.rb_device().context.info, size, rb.bins, std::size_t(width) * height, bundle_chains(rb),
                          scene.has_shading_normals());
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    s.geometry = build_bundle_geometry(scene, s.scene.patches);
    s.rb_pass_accum = &pass_accumulator(s, s.rb_accum);
    build_rb_pass(s, *s.rb_pass_accum);
  }
}

// PT timed on a pass of its own at a smaller size of the same view (passes/combined.h), on the first
// PT device; RB on its own pass.
RatioProbe run_probe(RenderState& s, double pt_time_share) {
  const RenderSpec& o = s.spec;
  const ProbeImageSize size = probe_image_size(s.scene.width, s.scene.height);
  Accumulator probe_accum(size.width, size.height, false);
  PathTracerPass probe_pt(s.pt_device().context, s.pt_device().scene,
                          pack_camera(s.scene.scene.camera, size.width, size.height), s.pt_settings, probe_accum);
  return probe_ratio(probe_pt, std::size_t(s.scene.width) * s.scene.height, *s.rb, *s.rb_pass_accum,
                     RatioProbeBudget{o.seconds, o.spp, o.iterations, pt_time_share});
}

// The probe's round: its time share's on one device; on several, where PT and RB run at the same
// time, the round that keeps both busy (PT's time per sample shared by its devices).
void choose_probed_shape(RenderState& s) {
  if (s.several_devices())
    s.probe->chosen = concurrent_ratio_shape(s.probe->pt_seconds_per_spp / double(s.pt.size()),
                                             s.probe->rb_seconds_per_iteration);
  s.shape = s.probe->chosen;
}

// --ratio auto: the probe picks c (or a resumed render takes the checkpoint's); --eye-direct auto:
// shared below kEyeDirectSharedBelowSpp PT samples per pixel, or what a resumed render was saved with.
// Both passes get the chosen c's weights before the first counted sample.
void choose_auto_settings(RenderState& s, RenderObserver& observer) {
  const RenderSpec& o = s.spec;
  if (ratio_is_auto(o)) {
    if (s.resumed) {
      if (std::optional<RoundShape> saved = round_of_key(s.resumed->options)) s.shape = *saved;
    } else {
      // The share for the eye-direct choice known now (auto counts as shared until it is resolved).
      s.probe = run_probe(s, auto_ratio_pt_time_share(s.light_sampling && !s.eye_direct_shared));
      choose_probed_shape(s);
    }
  }
  const bool eye_direct_auto = s.light_sampling && s.use_pt && s.use_rb && o.eye_direct == "auto";
  // Where it is pt, the ray-bundle pass is made again without the eye chain.
  if (eye_direct_auto && !s.pt.empty() && s.rb && s.weight_mode == BP_WEIGHTS_PRODUCT) {
    std::optional<bool> saved = s.resumed ? eye_direct_shared_of_key(s.resumed->options) : std::nullopt;
    if (saved) {
      s.eye_direct_shared = *saved;
    } else {
      // A --time budget needs the probe's costs: probed here when --ratio did not probe already.
      double t_pt = s.probe ? s.probe->pt_seconds_per_spp : 0.0, t_rb = s.probe ? s.probe->rb_seconds_per_iteration : 0.0;
      if (!s.probe && o.seconds > 0.0 && !o.spp && !o.iterations) {
        const RatioProbe timing = run_probe(s, kAutoRatioPtTimeShareEyeShared);
        t_pt = timing.pt_seconds_per_spp;
        t_rb = timing.rb_seconds_per_iteration;
      }
      const double spp = expected_pt_spp(*s.shape, o.spp, o.iterations, o.seconds, t_pt, t_rb);
      s.eye_direct_shared = spp < kEyeDirectSharedBelowSpp;
      observer.note(printf_text("--eye-direct auto: %s (about %.0f PT samples per pixel)",
                                s.eye_direct_shared ? "shared" : "pt", spp));
    }
    if (!s.eye_direct_shared && s.probe) {  // PT's alone: the ratio for that share (kAutoRatioPtTimeShareEyePt)
      s.probe->pt_time_share = auto_ratio_pt_time_share(true);
      s.probe->chosen =
          auto_ratio_shape(s.probe->pt_seconds_per_spp, s.probe->rb_seconds_per_iteration, s.probe->pt_time_share);
      choose_probed_shape(s);
    }
    if (!s.eye_direct_shared) {
      for (auto& pt : s.pt) pt->set_eye_direct_shared(false);
      s.rb_settings.eye_direct_shared = false;
      build_rb_pass(s, *s.rb_pass_accum);
    }
  }
  if (s.probe && s.several_devices())
    observer.note(printf_text("--ratio auto: c = %s (PT %.4g s per sample per pixel over %zu device(s), RB %.4g s per "
                              "iteration, at the same time: the round that keeps both busy; probe %.2f s)",
                              ratio_text(*s.shape).c_str(), s.probe->pt_seconds_per_spp / double(s.pt.size()),
                              s.pt.size(), s.probe->rb_seconds_per_iteration, s.probe->probe_seconds));
  else if (s.probe)
    observer.note(printf_text("--ratio auto: c = %s (PT %.4g s per sample per pixel, RB %.4g s per iteration, PT "
                              "time share %.2f; probe %.2f s)",
                              ratio_text(*s.shape).c_str(), s.probe->pt_seconds_per_spp,
                              s.probe->rb_seconds_per_iteration, s.probe->pt_time_share, s.probe->probe_seconds));
  if (ratio_is_auto(o)) {
    s.ratio_n2_over_n1 = combined_weights(s.weight_mode, *s.shape).ratio_n2_over_n1;
    for (auto& pt : s.pt) pt->set_weight_ratio(s.ratio_n2_over_n1);
    s.rb->set_weight_ratio(s.ratio_n2_over_n1);
  }
}

// A resumed render starts from the checkpoint's accumulators, ray-bundle state and round count.
void resume(RenderState& s) {
  const RenderSpec& o = s.spec;
  s.key = options_key(o, s.scene.width, s.scene.height, s.scene.patch_size, s.rb ? s.rb_settings.bins : 0, s.shape,
                      s.eye_direct_shared ? "shared" : "pt");
  if (!s.resumed) return;
  Checkpoint& c = *s.resumed;
  if (c.options != s.key)
    throw UsageError("--resume " + o.resume_path + " was saved with other options:\n  saved: " + c.options +
                     "\n  now:   " + s.key);
  if (!s.pt.empty() && c.pt) s.pt_accum = *c.pt;
  if (s.rb && c.rb) s.rb_accum = *c.rb;
  if (s.rb && c.rb_state) s.rb->load_state(*c.rb_state);
  s.first_round = c.rounds;
  s.earlier_seconds = c.render_seconds;
}

// The error estimate (DESIGN.md §9): batches of both estimators together, each long enough for RB's
// chain -- kErrorBatchRbIterations iterations (--error-batch), in rounds of the combination.
void start_error_estimate(RenderState& s) {
  const RenderSpec& o = s.spec;
  const std::uint64_t rb_batch_iterations = o.error_batch ? o.error_batch : kErrorBatchRbIterations;
  const std::uint64_t error_batch_rounds =
      !s.rb ? 1 : s.shape ? (rb_batch_iterations + s.shape->rb_iterations - 1) / s.shape->rb_iterations
                          : rb_batch_iterations;
  // The image times the rounds: pt.sum / N1 + rb.sum / N2 per round (eq. 3; N1 = N2 = 1 alone).
  if (!s.pt.empty() && (!s.shape || s.shape->pt_samples > 0)) {
    s.round_sums.first = &s.pt_accum.sum;
    s.round_sums.first_scale = s.shape ? 1.0 / s.shape->pt_samples : 1.0;
  }
  if (s.rb) {
    s.round_sums.second = &s.rb_accum.sum;
    s.round_sums.second_scale = s.shape ? 1.0 / s.shape->rb_iterations : 1.0;
  }
  const int width = s.scene.width, height = s.scene.height;
  if (s.resumed && s.resumed->error_estimate)
    s.error_estimate.emplace(BatchMeansErrorEstimate::from_state(*s.resumed->error_estimate, width, height));
  else
    s.error_estimate.emplace(width, height, error_batch_rounds, o.error_levels, s.first_round,
                             s.first_round ? &s.round_sums : nullptr);
  s.estimated_rel_mse = s.error_estimate->estimated_rel_mse(s.round_sums);
}

void save_checkpoint(RenderState& s, std::uint64_t rounds, double seconds) {
  Checkpoint c;
  c.options = s.key;
  c.rounds = rounds;
  c.render_seconds = s.earlier_seconds + seconds;
  if (!s.pt.empty()) c.pt = s.pt_accum;
  if (s.rb) {
    c.rb = s.rb_accum;
    c.rb_state = s.rb->save_state();
  }
  c.error_estimate = s.error_estimate->state();
  write_checkpoint(s.spec.checkpoint_path, c);
}

// What the render loop runs, and its round target.
void build_schedule(RenderState& s) {
  const RenderSpec& o = s.spec;
  s.pass = !s.pt.empty() ? static_cast<ProgressivePass*>(s.pt.front().get()) : s.rb.get();
  s.rounds = o.mode == "rb" ? o.iterations : o.spp;
  if (s.several_devices()) {
    std::vector<DeviceLane> lanes;
    for (std::size_t i = 0; i < s.devices.size(); ++i) {
      DeviceLane lane;
      lane.device_index = s.devices[i]->context.info.index;
      lane.device_name = s.devices[i]->context.info.device_name;
      for (std::size_t k = 0; k < s.roles.pt.size(); ++k)
        if (s.roles.pt[k] == i) {
          lane.pt = s.pt[k].get();
          lane.accum = s.pt_pass_accums[k];
        }
      if (s.rb && s.roles.rb == i && !lane.pt) {
        lane.rb = s.rb.get();
        lane.accum = s.rb_pass_accum;
      }
      if (lane.pt || lane.rb) lanes.push_back(lane);
    }
    auto parallel = std::make_unique<ParallelPass>(std::move(lanes), s.shape, s.pt_accum, s.rb_accum);
    s.lanes = parallel.get();
    s.pass = parallel.get();
    s.schedule = std::move(parallel);
  } else if (s.shape) {
    s.schedule = std::make_unique<CombinedPass>(*s.pt.front(), *s.rb, *s.shape);
    s.pass = s.schedule.get();
  }
  if (s.shape) {
    s.rounds = o.spp ? (o.spp + s.shape->pt_samples - 1) / s.shape->pt_samples
                     : (o.iterations + s.shape->rb_iterations - 1) / s.shape->rb_iterations;
  }
}

std::string device_description(const RenderState& s) {
  std::string out;
  for (const auto& d : s.devices) out += (out.empty() ? "" : " + ") + d->context.description();
  return out;
}

void render_rounds(RenderState& s, RenderObserver& observer) {
  const RenderSpec& o = s.spec;
  std::uint64_t saved_rounds = s.first_round;
  double last_save = 0.0;
  observer.started();
  observer.note(printf_text("rendering %s (%dx%d, %s%s, %zu triangles, %u patches) on %s", o.scene.c_str(),
                            s.scene.width, s.scene.height, o.mode.c_str(),
                            s.shape ? (", weights " + o.weights).c_str() : "", s.scene.scene.triangles.size(),
                            s.scene.patches.patch_count, device_description(s).c_str()));
  for (std::size_t i : s.roles.idle)
    observer.note("warning: --mode " + o.mode + " runs on one device: " + s.devices[i]->context.info.device_name +
                  " stays idle");
  const double pixels = double(s.scene.width) * s.scene.height;
  const bool counts_iterations = o.mode == "rb" || (s.shape && s.shape->pt_samples == 0);
  const double samples_per_round = counts_iterations ? (s.shape ? s.shape->rb_iterations : 1.0)
                                                     : (s.shape ? s.shape->pt_samples * pixels : pixels);
  RenderBudget budget{s.rounds, o.seconds, {}};
  // --target-error: done once enough batches say the relMSE is at most X (checked after each batch).
  if (o.target_error > 0.0)
    budget.target_reached = [&] {
      return s.error_estimate->batches() >= kMinBatchesForTarget && s.estimated_rel_mse <= o.target_error;
    };
  s.outcome = run_progressive(
      *s.pass, budget, observer.stop_requested(),
      [&](const RenderProgress& p) {
        double secs = std::max(p.elapsed_seconds, 1e-9);
        s.error_estimate->add(p.rounds_done, s.round_sums);
        s.estimated_rel_mse = s.error_estimate->estimated_rel_mse(s.round_sums);
        RenderProgressReport report;
        report.fraction = p.fraction;
        if (o.target_error > 0.0 && std::isfinite(s.estimated_rel_mse) && p.rounds_done > s.first_round) {
          // relMSE ∝ 1/N: X is reached after N·relMSE/X rounds, at this run's seconds per round.
          const double rounds_needed = double(p.rounds_done) * s.estimated_rel_mse / o.target_error;
          const double seconds_per_round = p.elapsed_seconds / double(p.rounds_done - s.first_round);
          double eta = std::max(0.0, rounds_needed - double(p.rounds_done)) * seconds_per_round;
          if (o.seconds > 0.0) eta = std::min(eta, std::max(0.0, o.seconds - p.elapsed_seconds));
          report.eta_seconds = eta;
          report.fraction = std::max(report.fraction, std::min(1.0, o.target_error / s.estimated_rel_mse));
        }
        report.rate = double(p.rounds_done - s.first_round) * samples_per_round / secs;
        report.mrays_per_second = double(p.rays) / secs * 1e-6;
        report.elapsed_seconds = p.elapsed_seconds;
        report.rate_unit = counts_iterations ? "iterations/s" : "samples/s";
        report.estimated_rel_mse = s.estimated_rel_mse;
        observer.progress(report);
        if (!o.checkpoint_path.empty() && p.elapsed_seconds - last_save >= o.checkpoint_every) {
          save_checkpoint(s, p.rounds_done, p.elapsed_seconds);
          saved_rounds = p.rounds_done;
          last_save = p.elapsed_seconds;
        }
      },
      s.first_round);
  observer.finished();
  // After a device failed its passes are past the rounds the accumulators hold: the checkpoint keeps
  // its last save.
  if (!s.outcome.failure.empty()) return;
  if (!o.checkpoint_path.empty() && (saved_rounds != s.outcome.rounds || o.resume_path.empty()))
    save_checkpoint(s, s.outcome.rounds, s.outcome.seconds);
}

// Samples and iterations of the whole render, and each device's part of it.
void count_work(RenderState& s, RenderResult& r) {
  const std::uint64_t rounds = s.outcome.rounds;
  r.pt_samples = s.shape ? rounds * s.shape->pt_samples : (!s.pt.empty() ? rounds : 0);
  r.rb_iterations = s.shape ? rounds * s.shape->rb_iterations : (s.rb ? rounds : 0);
  r.device_failure = s.outcome.failure;
  if (!s.lanes) {  // one device: all of it (a resumed render's earlier runs too)
    const DeviceInfo& info = s.devices.front()->context.info;
    r.devices.push_back(DeviceWorkReport{info.index, info.device_name, r.pt_samples, r.rb_iterations, s.outcome.seconds});
    return;
  }
  for (const auto& device : s.devices) {  // in --device's order; an idle one did nothing
    const DeviceInfo& info = device->context.info;
    DeviceWorkReport report{info.index, info.device_name, 0, 0, 0.0};
    for (const DeviceLane& lane : s.lanes->lanes())
      if (lane.device_index == info.index)
        report = DeviceWorkReport{info.index, lane.device_name, lane.pt_samples, lane.rb_iterations, lane.busy_seconds};
    r.devices.push_back(report);
  }
}

}  // namespace

RenderJob::RenderJob(const RenderSpec& spec) : spec_(spec) {}
RenderJob::~RenderJob() = default;

RenderResult RenderJob::run(RenderObserver& observer) {
  RenderState s(spec_);
  s.scene = prepare_scene(spec_, [&](const std::string& line) { observer.note(line); });
  choose_round(s);
  open_devices(s);
  build_passes(s);
  if (!spec_.resume_path.empty()) s.resumed = read_checkpoint(spec_.resume_path);
  choose_auto_settings(s, observer);
  resume(s);
  start_error_estimate(s);
  build_schedule(s);
  render_rounds(s, observer);

  RenderResult r;
  r.outcome = s.outcome;
  r.width = s.scene.width;
  r.height = s.scene.height;
  r.combined = s.shape.has_value();
  r.mrays_per_second = s.outcome.seconds > 0 ? double(s.outcome.rays) / s.outcome.seconds * 1e-6 : 0.0;
  r.estimated_rel_mse = s.estimated_rel_mse;
  r.error_batches = s.error_estimate->batches();
  r.error_batch_rounds = s.error_estimate->batch_rounds();
  count_work(s, r);
  const RenderLayers layers = make_layers(s);
  write_images(s, layers, r);
  r.reference_metrics = compare_layers(s, layers);
  if (!spec_.stats_path.empty()) write_stats(s, r);
  return r;
}

}  // namespace bp

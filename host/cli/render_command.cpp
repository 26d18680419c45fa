// bundlepath render: scene -> device -> passes (pt, rb, or both combined) -> layers -> files.
#include "cli/commands.h"

#include "cli/interrupt.h"
#include "cli/progress.h"
#include "device/device_context.h"
#include "device/device_scene.h"
#include "device/kernel_features.h"
#include "image/accumulator.h"
#include "image/contact_sheet.h"
#include "image/error_estimate.h"
#include "image/image.h"
#include "image/stats_io.h"
#include "passes/checkpoint.h"
#include "passes/combined.h"
#include "passes/path_tracer.h"
#include "passes/ray_bundles.h"
#include "passes/render_loop.h"
#include "scene/bundle_geometry.h"
#include "scene/bvh.h"
#include "scene/gltf_loader.h"
#include "scene/patches.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

namespace bp {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::uint32_t weight_mode_of(const RenderOptions& o) {
  if (o.mode != "combined" || o.weights == "none") return BP_WEIGHTS_NONE;
  return o.weights == "paper" ? BP_WEIGHTS_PAPER : BP_WEIGHTS_PRODUCT;
}

std::uint32_t beta_heuristic_of(const RenderOptions& o) {
  return o.beta == "balance" ? BP_BETA_BALANCE : BP_BETA_CLAMPED;
}

ImageRGB sum_images(const ImageRGB& a, const ImageRGB& b) {
  ImageRGB out = a;
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] += b.rgb[i];
  return out;
}

// The layers of the output (DESIGN.md §7): "" is the combined image.
struct Layers {
  std::vector<std::pair<std::string, ImageRGB>> images;
  const ImageRGB* find(const std::string& name) const {
    for (const auto& [n, img] : images)
      if (n == name) return &img;
    return nullptr;
  }
};

// Everything that shapes the image, canonically: a checkpoint resumes only under the same.
// eye_direct: what the eye vertex's direct light is (shared or pt; --eye-direct auto resolved).
std::string options_key(const RenderOptions& o, int width, int height, float patch_size, std::uint32_t bins,
                        const std::optional<RoundShape>& shape, const std::string& eye_direct) {
  std::string key = "scene=" + std::filesystem::absolute(o.scene).lexically_normal().string() +
                    ";mode=" + o.mode + ";size=" + std::to_string(width) + "x" + std::to_string(height) +
                    ";seed=" + std::to_string(o.seed) + ";patch_size=" + std::to_string(patch_size) +
                    ";max_depth=" + std::to_string(o.max_depth) + ";layers=" + (o.all_layers ? "all" : "default") +
                    ";light_sampling=" + (light_sampling_applies(o) ? "on;light_selection=" + o.light_selection : "off") +
                    ";kernels=" + (o.generic_kernels ? "generic" : "specialised");
  if (o.environment != std::array<float, 3>{0.0f, 0.0f, 0.0f})
    key += ";environment=" + std::to_string(o.environment[0]) + "," + std::to_string(o.environment[1]) + "," +
           std::to_string(o.environment[2]);
  if (o.mode != "pt")
    key += ";bins=" + std::to_string(bins) + ";warmup=" + std::to_string(o.warmup) +
           (o.contact_depth >= 0.0f ? ";contact_depth=" + std::to_string(o.contact_depth) : "") +
           ";shading=" + (o.gouraud ? "gouraud" : "flat");
  if (shape)
    key += ";weights=" + o.weights + ";beta=" + o.beta + ";light_rate=" + std::to_string(o.light_rate) +
           ";eye_direct=" + eye_direct +
           ";round=" + std::to_string(shape->pt_samples) + "spp+" + std::to_string(shape->rb_iterations) + "it";
  return key;
}

// The round a checkpoint was saved with (its key's ";round=Nspp+Mit"), for --ratio auto's --resume.
std::optional<RoundShape> round_of_key(const std::string& key) {
  const std::string tag = ";round=";
  const std::size_t at = key.find(tag);
  if (at == std::string::npos) return std::nullopt;
  unsigned long long spp = 0, iterations = 0;
  if (std::sscanf(key.c_str() + at + tag.size(), "%lluspp+%lluit", &spp, &iterations) != 2 || iterations == 0)
    return std::nullopt;
  return RoundShape{std::uint32_t(spp), std::uint32_t(iterations)};
}

// The eye-direct choice a checkpoint was saved with (its key's ";eye_direct=shared|pt"), for
// --eye-direct auto's --resume.
std::optional<bool> eye_direct_shared_of_key(const std::string& key) {
  if (key.find(";eye_direct=shared") != std::string::npos) return true;
  if (key.find(";eye_direct=pt") != std::string::npos) return false;
  return std::nullopt;
}

std::string ratio_text(const RoundShape& shape) {
  return shape.rb_iterations == 1 ? std::to_string(shape.pt_samples) : "1/" + std::to_string(shape.rb_iterations);
}

}  // namespace

int run_render(const RenderOptions& o) {
  using clock = std::chrono::steady_clock;
  // The reference is read first: a wrong path should not cost a render.
  std::optional<ImageRGB> reference;
  if (!o.reference_path.empty()) reference = read_exr(o.reference_path);

  auto t_load = clock::now();
  Scene scene = load_gltf(o.scene);
  scene.environment = glm::vec3(o.environment[0], o.environment[1], o.environment[2]);
  for (const std::string& w : scene.warnings)
    if (!(scene.has_environment() && w.rfind("no emitter", 0) == 0))  // the environment lights it
      std::fprintf(stderr, "bundlepath: warning: %s: %s\n", o.scene.c_str(), w.c_str());
  if (!scene.lights.empty() && !light_sampling_applies(o))
    std::fprintf(stderr,
                 "bundlepath: warning: %s: %zu point/spot/directional light(s) are reached by light sampling only, which this run "
                 "does not use (--mode pt or --mode combined with product weights, without --no-light-sampling): "
                 "they stay dark\n",
                 o.scene.c_str(), scene.lights.size());
  double load_seconds = seconds_since(t_load);

  int width = o.width;
  int height = o.height;
  if (height == 0)
    height = scene.camera.aspect > 0.0f ? std::max(1, int(std::lround(width / scene.camera.aspect))) : width;
  if (reference && (reference->width != width || reference->height != height))
    throw UsageError("--reference " + o.reference_path + " is " + std::to_string(reference->width) + "x" +
                     std::to_string(reference->height) + " but the render is " + std::to_string(width) + "x" +
                     std::to_string(height) + " (set --width/--height to match)");

  float patch_size = o.patch_size > 0.0f ? o.patch_size : default_patch_size(scene);
  PatchLayout patches;
  try {
    patches = build_patch_layout(scene, patch_size);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  auto t_bvh = clock::now();
  FlatBvh bvh = build_bvh(scene.triangles);
  double bvh_seconds = seconds_since(t_bvh);

  const bool use_pt = o.mode != "rb", use_rb = o.mode != "pt";
  std::optional<RoundShape> shape;
  if (o.mode == "combined") {
    try {
      shape = round_shape(ratio_is_auto(o) ? 0.25 : o.ratio);  // auto: replaced by the probe's choice below
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  // The weights both passes use; --ratio 0 (no PT samples) runs RB unweighted, w_RB = 1.
  const CombinedWeights weights = shape ? combined_weights(weight_mode_of(o), *shape) : CombinedWeights{};
  const std::uint32_t weight_mode = weights.mode;
  float ratio_n2_over_n1 = weights.ratio_n2_over_n1;

  DeviceContext device(select_device(o.device));
  // The light tree and its per-patch receivers only where light sampling acts (power needs neither).
  const bool light_tree = light_sampling_applies(o) && o.light_selection == "tree";
  // One receiver per patch: refused before anything is built when it cannot fit the device.
  const std::size_t receiver_bytes = light_tree ? patches.patch_count * sizeof(LightReceiver) : 0;
  if (receiver_bytes > device.info.max_alloc_bytes || receiver_bytes > device.info.global_memory_bytes / 4)
    throw UsageError("the light tree needs " + std::to_string(receiver_bytes >> 20) + " MiB for its " +
                     std::to_string(patches.patch_count) + " receiving patches, more than " + device.info.device_name +
                     " offers (at most " + std::to_string(device.info.max_alloc_bytes >> 20) +
                     " MiB per buffer): raise --patch-size or use --light-selection power");
  // All textures' texels are one buffer: refused before anything is built when it cannot fit the device.
  const std::size_t texel_bytes = scene.has_textures() ? scene.texels.size() * sizeof(std::uint32_t) : 0;
  if (texel_bytes > device.info.max_alloc_bytes || texel_bytes > device.info.global_memory_bytes / 4)
    throw UsageError("the scene's textures need " + std::to_string(texel_bytes >> 20) + " MiB, more than " +
                     device.info.device_name + " offers (at most " + std::to_string(device.info.max_alloc_bytes >> 20) +
                     " MiB per buffer)");
  DeviceScene device_scene(device, scene, patches, bvh,
                           light_tree ? BP_LIGHT_SELECTION_TREE : BP_LIGHT_SELECTION_POWER);
  const CameraParams camera = pack_camera(scene.camera, width, height);
  const bool light_sampling = light_sampling_applies(o) && device_scene.light_count > 0;
  const float light_rate =
      o.light_rate > 0.0f ? o.light_rate : default_light_rate(patches.patch_count, std::size_t(width) * height);
  const std::string kernel_opts = o.generic_kernels ? "" : kernel_options(features_for(scene, light_sampling));
  // Both passes or neither: the split is exact only when PT and RB weight the eye vertex alike.
  // --eye-direct auto builds them shared (RB's chains are a superset) and decides below.
  const bool eye_direct_auto = light_sampling && use_pt && use_rb && o.eye_direct == "auto";
  bool eye_direct_shared = light_sampling && (o.eye_direct == "shared" || eye_direct_auto);
  Accumulator pt_accum(width, height, o.all_layers), rb_accum(width, height, o.all_layers);

  std::unique_ptr<PathTracerPass> pt;
  PathTracerSettings pt_settings;  // for --ratio auto's probe pass
  if (use_pt) {
    PathTracerSettings settings;
    settings.seed = o.seed;
    settings.max_depth = o.max_depth;
    settings.weight_mode = weight_mode;
    settings.weight_ratio = ratio_n2_over_n1;
    settings.beta_heuristic = beta_heuristic_of(o);
    settings.rb_light_rate = light_rate;
    settings.light_sampling = light_sampling;
    settings.eye_direct_shared = eye_direct_shared;
    settings.kernel_options = kernel_opts;
    pt = std::make_unique<PathTracerPass>(device, device_scene, camera, settings, pt_accum);
    pt_settings = settings;
  }
  std::unique_ptr<RayBundlePass> rb;
  std::optional<BundleGeometry> geometry;
  RayBundleSettings rb_settings;
  if (use_rb) {
    const BundleSize size = bundle_size(scene, patches);
    rb_settings.seed = o.seed;
    rb_settings.bins = o.bins ? o.bins : default_bins(size);
    if (o.contact_depth >= 0.0f) rb_settings.contact_depth_fraction = o.contact_depth;
    rb_settings.warmup = o.warmup;
    rb_settings.gouraud = o.gouraud;
    rb_settings.light_sampling = light_sampling;
    rb_settings.eye_direct_shared = eye_direct_shared;
    rb_settings.kernel_options = kernel_opts;
    rb_settings.weight_mode = weight_mode;
    rb_settings.weight_ratio = ratio_n2_over_n1;
    rb_settings.beta_heuristic = beta_heuristic_of(o);
    rb_settings.light_rate = light_rate;
    rb_settings.keep_raw = o.all_layers;
    try {
      check_bundle_memory(device.info, size, rb_settings.bins, std::size_t(width) * height, bundle_chains(rb_settings),
                          scene.has_shading_normals(), scene.has_textures());
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    geometry = build_bundle_geometry(scene, patches);
    rb = std::make_unique<RayBundlePass>(device, device_scene, *geometry, camera, rb_settings, rb_accum);
  }
  // --ratio auto: the probe picks c (or a resumed render takes the checkpoint's), and both passes
  // get its weights before the first counted sample.
  std::optional<RatioProbe> probe;
  std::optional<Checkpoint> resumed;
  if (!o.resume_path.empty()) resumed = read_checkpoint(o.resume_path);
  if (ratio_is_auto(o)) {
    if (resumed) {
      if (std::optional<RoundShape> saved = round_of_key(resumed->options)) shape = *saved;
    } else {
      // PT is timed on a pass of its own at a smaller size of the same view (passes/combined.h).
      const ProbeImageSize size = probe_image_size(width, height);
      Accumulator probe_accum(size.width, size.height, false);
      PathTracerPass probe_pt(device, device_scene, pack_camera(scene.camera, size.width, size.height), pt_settings,
                              probe_accum);
      // The share for the eye-direct choice known now (auto counts as shared until it is resolved).
      probe = probe_ratio(probe_pt, std::size_t(width) * height, *rb, rb_accum,
                          RatioProbeBudget{o.seconds, o.spp, o.iterations,
                                           auto_ratio_pt_time_share(light_sampling && !eye_direct_shared)});
      shape = probe->chosen;
    }
  }
  // --eye-direct auto: shared below kEyeDirectSharedBelowSpp PT samples per pixel (a --time budget
  // needs the probe's costs: probed here when --ratio did not probe already), or what a resumed
  // render was saved with. Where it is pt, the ray-bundle pass is made again without the eye chain.
  if (eye_direct_auto && pt && rb && weight_mode == BP_WEIGHTS_PRODUCT) {
    std::optional<bool> saved = resumed ? eye_direct_shared_of_key(resumed->options) : std::nullopt;
    if (saved) {
      eye_direct_shared = *saved;
    } else {
      double t_pt = probe ? probe->pt_seconds_per_spp : 0.0, t_rb = probe ? probe->rb_seconds_per_iteration : 0.0;
      if (!probe && o.seconds > 0.0 && !o.spp && !o.iterations) {
        const ProbeImageSize size = probe_image_size(width, height);
        Accumulator probe_accum(size.width, size.height, false);
        PathTracerPass probe_pt(device, device_scene, pack_camera(scene.camera, size.width, size.height), pt_settings,
                                probe_accum);
        const RatioProbe timing = probe_ratio(probe_pt, std::size_t(width) * height, *rb, rb_accum,
                                              RatioProbeBudget{o.seconds, o.spp, o.iterations});
        t_pt = timing.pt_seconds_per_spp;
        t_rb = timing.rb_seconds_per_iteration;
      }
      const double spp = expected_pt_spp(*shape, o.spp, o.iterations, o.seconds, t_pt, t_rb);
      eye_direct_shared = spp < kEyeDirectSharedBelowSpp;
      std::fprintf(stderr, "bundlepath: --eye-direct auto: %s (about %.0f PT samples per pixel)\n",
                   eye_direct_shared ? "shared" : "pt", spp);
    }
    if (!eye_direct_shared && probe) {  // PT's alone: the ratio for that share (kAutoRatioPtTimeShareEyePt)
      probe->pt_time_share = auto_ratio_pt_time_share(true);
      probe->chosen = auto_ratio_shape(probe->pt_seconds_per_spp, probe->rb_seconds_per_iteration, probe->pt_time_share);
      shape = probe->chosen;
    }
    if (!eye_direct_shared) {
      pt->set_eye_direct_shared(false);
      rb_settings.eye_direct_shared = false;
      rb = std::make_unique<RayBundlePass>(device, device_scene, *geometry, camera, rb_settings, rb_accum);
    }
  }
  if (probe)
    std::fprintf(stderr,
                 "bundlepath: --ratio auto: c = %s (PT %.4g s per sample per pixel, RB %.4g s per iteration, PT "
                 "time share %.2f; probe %.2f s)\n",
                 ratio_text(*shape).c_str(), probe->pt_seconds_per_spp, probe->rb_seconds_per_iteration,
                 probe->pt_time_share, probe->probe_seconds);
  if (ratio_is_auto(o)) {  // both passes get the chosen c's weights before the first counted sample
    ratio_n2_over_n1 = combined_weights(weight_mode, *shape).ratio_n2_over_n1;
    pt->set_weight_ratio(ratio_n2_over_n1);
    rb->set_weight_ratio(ratio_n2_over_n1);
  }
  // A resumed render starts from the checkpoint's accumulators, ray-bundle state and round count.
  std::uint64_t first_round = 0;
  double earlier_seconds = 0.0;
  const std::string key = options_key(o, width, height, patch_size, rb ? rb_settings.bins : 0, shape,
                                      eye_direct_shared ? "shared" : "pt");
  if (resumed) {
    Checkpoint& c = *resumed;
    if (c.options != key)
      throw UsageError("--resume " + o.resume_path + " was saved with other options:\n  saved: " + c.options +
                       "\n  now:   " + key);
    if (pt && c.pt) pt_accum = *c.pt;
    if (rb && c.rb) rb_accum = *c.rb;
    if (rb && c.rb_state) rb->load_state(*c.rb_state);
    first_round = c.rounds;
    earlier_seconds = c.render_seconds;
  }
  // The error estimate (DESIGN.md §9): batches of both estimators together, each long enough for
  // RB's chain -- kErrorBatchRbIterations iterations (--error-batch), in rounds of the combination.
  const std::uint64_t rb_batch_iterations = o.error_batch ? o.error_batch : kErrorBatchRbIterations;
  const std::uint64_t error_batch_rounds =
      !rb ? 1 : shape ? (rb_batch_iterations + shape->rb_iterations - 1) / shape->rb_iterations : rb_batch_iterations;
  // The image times the rounds: pt.sum / N1 + rb.sum / N2 per round (eq. 3; N1 = N2 = 1 alone).
  RoundSums round_sums;
  if (pt && (!shape || shape->pt_samples > 0)) {
    round_sums.first = &pt_accum.sum;
    round_sums.first_scale = shape ? 1.0 / shape->pt_samples : 1.0;
  }
  if (rb) {
    round_sums.second = &rb_accum.sum;
    round_sums.second_scale = shape ? 1.0 / shape->rb_iterations : 1.0;
  }
  BatchMeansErrorEstimate error_estimate =
      resumed && resumed->error_estimate
          ? BatchMeansErrorEstimate::from_state(*resumed->error_estimate, width, height)
          : BatchMeansErrorEstimate(width, height, error_batch_rounds, o.error_levels, first_round,
                                    first_round ? &round_sums : nullptr);
  double estimated_rel_mse = error_estimate.estimated_rel_mse(round_sums);
  std::uint64_t saved_rounds = first_round;
  auto save_checkpoint = [&](std::uint64_t rounds, double seconds) {
    Checkpoint c;
    c.options = key;
    c.rounds = rounds;
    c.render_seconds = earlier_seconds + seconds;
    if (pt) c.pt = pt_accum;
    if (rb) {
      c.rb = rb_accum;
      c.rb_state = rb->save_state();
    }
    c.error_estimate = error_estimate.state();
    write_checkpoint(o.checkpoint_path, c);
    saved_rounds = rounds;
  };
  double last_save = 0.0;

  std::unique_ptr<CombinedPass> combined;
  ProgressivePass* pass = pt ? static_cast<ProgressivePass*>(pt.get()) : rb.get();
  std::uint64_t rounds = o.mode == "rb" ? o.iterations : o.spp;
  if (shape) {
    combined = std::make_unique<CombinedPass>(*pt, *rb, *shape);
    pass = combined.get();
    rounds = o.spp ? (o.spp + shape->pt_samples - 1) / shape->pt_samples
                   : (o.iterations + shape->rb_iterations - 1) / shape->rb_iterations;
  }

  install_interrupt_handlers();
  std::fprintf(stderr, "bundlepath: rendering %s (%dx%d, %s%s, %zu triangles, %u patches) on %s\n", o.scene.c_str(),
               width, height, o.mode.c_str(), shape ? (", weights " + o.weights).c_str() : "",
               scene.triangles.size(), patches.patch_count, device.description().c_str());
  ProgressBar bar(o.mode);
  const double pixels = double(width) * height;
  const bool counts_iterations = o.mode == "rb" || (shape && shape->pt_samples == 0);
  const double samples_per_round =
      counts_iterations ? (shape ? shape->rb_iterations : 1.0) : (shape ? shape->pt_samples * pixels : pixels);
  RenderBudget budget{rounds, o.seconds, {}};
  // --target-error: done once enough batches say the relMSE is at most X (checked after each batch).
  if (o.target_error > 0.0)
    budget.target_reached = [&] {
      return error_estimate.batches() >= kMinBatchesForTarget && estimated_rel_mse <= o.target_error;
    };
  RenderOutcome outcome = run_progressive(
      *pass, budget, stop_requested(),
      [&](const RenderProgress& p) {
        double secs = std::max(p.elapsed_seconds, 1e-9);
        error_estimate.add(p.rounds_done, round_sums);
        estimated_rel_mse = error_estimate.estimated_rel_mse(round_sums);
        double fraction = p.fraction, eta = NAN;
        if (o.target_error > 0.0 && std::isfinite(estimated_rel_mse) && p.rounds_done > first_round) {
          // relMSE ∝ 1/N: X is reached after N·relMSE/X rounds, at this run's seconds per round.
          const double rounds_needed = double(p.rounds_done) * estimated_rel_mse / o.target_error;
          const double seconds_per_round = p.elapsed_seconds / double(p.rounds_done - first_round);
          eta = std::max(0.0, rounds_needed - double(p.rounds_done)) * seconds_per_round;
          if (o.seconds > 0.0) eta = std::min(eta, std::max(0.0, o.seconds - p.elapsed_seconds));
          fraction = std::max(fraction, std::min(1.0, o.target_error / estimated_rel_mse));
        }
        bar.update(fraction, double(p.rounds_done - first_round) * samples_per_round / secs,
                   double(p.rays) / secs * 1e-6, p.elapsed_seconds, counts_iterations ? "iterations/s" : "samples/s",
                   estimated_rel_mse, eta);
        if (!o.checkpoint_path.empty() && p.elapsed_seconds - last_save >= o.checkpoint_every) {
          save_checkpoint(p.rounds_done, p.elapsed_seconds);
          last_save = p.elapsed_seconds;
        }
      },
      first_round);
  bar.finish();
  if (!o.checkpoint_path.empty() && (saved_rounds != outcome.rounds || o.resume_path.empty()))
    save_checkpoint(outcome.rounds, outcome.seconds);

  // Layers: R,G,B = pt + rb of the weighted images (eq. 3); pt, rb; pt_raw, rb_raw when asked for.
  Layers layers;
  ImageRGB pt_image = pt ? pt_accum.mean() : ImageRGB(width, height);
  ImageRGB rb_image = rb ? rb_accum.mean() : ImageRGB(width, height);
  layers.images.emplace_back("", sum_images(pt_image, rb_image));
  if (shape) {
    layers.images.emplace_back("pt", pt_image);
    layers.images.emplace_back("rb", rb_image);
  }
  if (o.all_layers) {
    if (pt) layers.images.emplace_back("pt_raw", pt_accum.raw_mean());
    if (rb) layers.images.emplace_back("rb_raw", rb_accum.raw_mean());
  }

  std::filesystem::path prefix(o.out_prefix);
  if (prefix.has_parent_path()) std::filesystem::create_directories(prefix.parent_path());
  const std::string exr_path = o.out_prefix + ".exr", png_path = o.out_prefix + ".png";
  std::vector<ImageLayer> exr_layers;
  for (const auto& [name, img] : layers.images) exr_layers.push_back({name, &img});
  // Each pixel's standard error of the combined image (DESIGN.md §9), beside the layers.
  const ImageRGB standard_error = error_estimate.standard_error();
  exr_layers.push_back({"stderr", &standard_error});
  write_exr(exr_path, exr_layers);
  write_png(png_path, layers.images.front().second, o.exposure);
  if (!o.contact_sheet_path.empty()) {
    const ImageRGB* combined_image = &layers.images.front().second;
    write_contact_sheet(o.contact_sheet_path,
                        {{"non-weighted PT", layers.find("pt_raw")},
                         {"weighted PT", shape ? layers.find("pt") : nullptr},
                         {"combined", combined_image},
                         {"non-weighted RB", layers.find("rb_raw")},
                         {"weighted RB", shape ? layers.find("rb") : nullptr},
                         {"reference", reference ? &*reference : nullptr}},
                        o.exposure);
  }

  nlohmann::json metrics;
  if (reference) {
    for (const auto& [name, img] : layers.images) {
      ErrorMetrics m = compare_images(img, *reference);
      const std::string key = name.empty() ? "combined" : name;
      metrics[key] = {{"rel_mse", m.rel_mse}, {"rmse", m.rmse}, {"mean_bias", m.mean_bias},
                      {"relative_bias", m.reference_mean != 0.0 ? m.mean_bias / m.reference_mean : 0.0}};
      std::fprintf(stderr, "bundlepath: %-8s vs reference: relMSE %.4g  RMSE %.4g  mean bias %+.4g\n", key.c_str(),
                   m.rel_mse, m.rmse, m.mean_bias);
    }
  }

  const std::uint64_t pt_samples = shape ? outcome.rounds * shape->pt_samples : (pt ? outcome.rounds : 0);
  const std::uint64_t rb_iterations = shape ? outcome.rounds * shape->rb_iterations : (rb ? outcome.rounds : 0);
  double mrays_per_second = outcome.seconds > 0 ? double(outcome.rays) / outcome.seconds * 1e-6 : 0.0;
  if (!o.stats_path.empty()) {
    nlohmann::json stats;
    stats["scene"] = o.scene;
    stats["device"] = device.description();
    stats["mode"] = o.mode;
    stats["width"] = width;
    stats["height"] = height;
    stats["spp"] = pt_samples;
    stats["seed"] = o.seed;
    stats["triangles"] = scene.triangles.size();
    stats["patches"] = patches.patch_count;
    stats["patch_size"] = patch_size;
    stats["scene_device_bytes"] = device_scene.bytes;  // BVH, shading, materials, lights, light tree, receivers, textures
    stats["texture_device_bytes"] = device_scene.texture_bytes;  // texels, views, texcoords, patch means
    stats["load_seconds"] = load_seconds;
    stats["bvh_build_seconds"] = bvh_seconds;
    double build_seconds = 0.0;
    bool from_cache = true;
    for (const ProgressivePass* part : pass->parts()) {
      build_seconds += part->program().build_seconds;
      from_cache = from_cache && part->program().from_cache;
      for (const auto& [name, t] : part->launcher().totals())
        stats["launches"][name] = {{"count", t.launches}, {"device_seconds", t.device_seconds}};
    }
    stats["kernel_build_seconds"] = build_seconds;
    stats["kernel_from_cache"] = from_cache;
    stats["render_seconds"] = outcome.seconds;
    stats["rays"] = outcome.rays;
    stats["mrays_per_second"] = mrays_per_second;
    stats["nan_or_inf_samples"] = outcome.nonfinite_samples;
    stats["interrupted"] = outcome.interrupted;
    stats["light_sampling"] = light_sampling;
    stats["kernel_options"] = kernel_opts;
    stats["lights"] = device_scene.light_count;
    if (light_sampling) stats["light_selection"] = o.light_selection;
    if (!o.resume_path.empty()) stats["resumed_from_rounds"] = first_round;
    if (!o.checkpoint_path.empty()) stats["checkpoint"] = o.checkpoint_path;
    if (shape) {
      stats["weights"] = o.weights;
      if (weight_mode == BP_WEIGHTS_PRODUCT) stats["beta"] = o.beta;
      if (light_sampling && rb) stats["rb_light_rate"] = light_rate;
      if (light_sampling && rb) stats["eye_direct"] = eye_direct_shared ? "shared" : "pt";
      stats["ratio"] = shape->ratio();
      if (probe)
        stats["ratio_auto"] = {{"chosen", shape->ratio()},
                               {"pt_seconds_per_spp", probe->pt_seconds_per_spp},
                               {"rb_seconds_per_iteration", probe->rb_seconds_per_iteration},
                               {"pt_time_share", probe->pt_time_share},
                               {"probe_pt_samples", probe->pt_samples},
                               {"probe_pt_size", std::to_string(probe->pt_image.width) + "x" +
                                                     std::to_string(probe->pt_image.height)},
                               {"probe_rb_iterations", probe->rb_iterations},
                               {"probe_seconds", probe->probe_seconds},
                               {"probe_first_launch_seconds", probe->first_launch_seconds}};
      else if (ratio_is_auto(o))
        stats["ratio_auto"] = {{"chosen", shape->ratio()}, {"from_checkpoint", true}};
      stats["rounds"] = outcome.rounds;
    }
    if (rb) {
      const double iterations = double(rb_iterations) + o.warmup;
      stats["iterations"] = rb_iterations;
      stats["warmup_iterations"] = o.warmup;
      stats["bins"] = rb->bins();
      stats["contact_depth"] = rb_settings.contact_depth_fraction;
      stats["elements"] = geometry->elements.size();
      stats["fragments_per_iteration"] = iterations > 0 ? double(outcome.fragments) / iterations : 0.0;
      stats["ms_per_iteration"] = rb_iterations && !shape ? outcome.seconds * 1e3 / iterations : 0.0;
      stats["fragments_per_second"] = outcome.seconds > 0 ? double(outcome.fragments) / outcome.seconds : 0.0;
      stats["rb_device_bytes_estimate"] = estimate_bundle_memory(bundle_size(scene, patches), rb->bins(),
                                                                 std::size_t(width) * height, bundle_chains(rb_settings),
                                                                 scene.has_shading_normals(), scene.has_textures());
      stats["rb_chains"] = bundle_chains(rb_settings);
    }
    if (reference) stats["reference"] = {{"path", o.reference_path}, {"layers", metrics}};
    stats["estimated_rel_mse"] = estimated_rel_mse;  // NaN (null) before two batches
    nlohmann::json levels = nlohmann::json::array();
    for (int j = 0; j < error_estimate.levels(); ++j)
      levels.push_back({{"batch_rounds", error_estimate.batch_rounds(j)},
                        {"batches", error_estimate.batches(j)},
                        {"estimated_rel_mse", error_estimate.estimated_rel_mse(round_sums, j)}});
    stats["error_estimate"] = {{"batch_rounds", error_estimate.batch_rounds()},
                               {"batches", error_estimate.batches()},
                               {"levels", levels}};
    if (rb) stats["error_estimate"]["rb_batch_iterations"] = error_estimate.batch_rounds() * (shape ? shape->rb_iterations : 1);
    if (o.target_error > 0.0) {
      stats["target_error"] = o.target_error;
      stats["target_reached"] = outcome.target_reached;
    }
    write_json_file(o.stats_path, stats);
  }
  std::string done = shape ? std::to_string(pt_samples) + " spp + " + std::to_string(rb_iterations) + " iterations"
                     : pt  ? std::to_string(pt_samples) + " spp"
                           : std::to_string(rb_iterations) + " iterations";
  std::fprintf(stderr, "bundlepath: %s%s at %dx%d in %.2f s (%.2f Mrays/s) -> %s, %s\n",
               outcome.interrupted ? "interrupted after " : "", done.c_str(), width, height, outcome.seconds,
               mrays_per_second, exr_path.c_str(), png_path.c_str());
  if (std::isfinite(estimated_rel_mse))
    std::fprintf(stderr, "bundlepath: estimated relMSE %.3g (noise only: from %llu batches of at least %llu rounds)%s\n",
                 estimated_rel_mse, static_cast<unsigned long long>(error_estimate.batches()),
                 static_cast<unsigned long long>(error_estimate.batch_rounds()),
                 o.target_error > 0.0 ? (outcome.target_reached ? ": --target-error reached" : ": --target-error not reached")
                                      : "");
  if (outcome.nonfinite_samples)
    std::fprintf(stderr, "bundlepath: warning: %llu NaN/Inf samples were dropped\n",
                 static_cast<unsigned long long>(outcome.nonfinite_samples));
  return outcome.interrupted ? 130 : 0;
}

}  // namespace bp

#include "cli/commands.h"

#include "cli/interrupt.h"
#include "cli/progress.h"
#include "device/device_context.h"
#include "device/device_scene.h"
#include "image/accumulator.h"
#include "image/image.h"
#include "image/stats_io.h"
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

}  // namespace

int run_devices() {
  for (const DeviceInfo& d : list_devices()) {
    std::printf("[%d] %s  (%s; %s; driver %s; %u compute units; %llu MiB)\n", d.index, d.device_name.c_str(),
                d.platform_name.c_str(), d.is_gpu ? "GPU" : "CPU", d.driver_version.c_str(), d.compute_units,
                static_cast<unsigned long long>(d.global_memory_bytes >> 20));
  }
  return 0;
}

int run_compare(const std::vector<std::string>& args) {
  std::vector<std::string> files;
  std::string layer;
  bool json = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--json") json = true;
    else if (args[i] == "--layer") {
      if (i + 1 >= args.size()) throw UsageError("--layer: missing value");
      layer = args[++i];
    } else if (args[i].rfind("--", 0) == 0) throw UsageError("unknown option '" + args[i] + "' for compare");
    else files.push_back(args[i]);
  }
  if (files.size() != 2) throw UsageError("usage: bundlepath compare IMAGE.exr REFERENCE.exr [--layer NAME] [--json]");
  ImageRGB image = read_exr(files[0], layer), reference = read_exr(files[1]);
  if (image.width != reference.width || image.height != reference.height)
    throw UsageError(files[0] + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) + " but " +
                     files[1] + " is " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
  ErrorMetrics m = compare_images(image, reference);
  const double level = m.reference_mean != 0.0 ? m.reference_mean : 1.0;
  if (json) {
    nlohmann::json out = {{"rel_mse", m.rel_mse}, {"rmse", m.rmse}, {"mean_bias", m.mean_bias},
                          {"mean_abs_difference", m.mean_abs_difference}, {"reference_mean", m.reference_mean},
                          {"relative_bias", m.mean_bias / level},
                          {"relative_mean_abs_difference", m.mean_abs_difference / level}};
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("relMSE %.4g  RMSE %.4g  bias %+.4g (%+.2f %%)  mean |difference| %.4g (%.2f %% of the mean)\n",
                m.rel_mse, m.rmse, m.mean_bias, 100.0 * m.mean_bias / level, m.mean_abs_difference,
                100.0 * m.mean_abs_difference / level);
  }
  return 0;
}

int run_render(const RenderOptions& o) {
  using clock = std::chrono::steady_clock;
  auto t_load = clock::now();
  Scene scene = load_gltf(o.scene);
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "bundlepath: warning: %s: %s\n", o.scene.c_str(), w.c_str());
  double load_seconds = seconds_since(t_load);

  int width = o.width;
  int height = o.height;
  if (height == 0)
    height = scene.camera.aspect > 0.0f ? std::max(1, int(std::lround(width / scene.camera.aspect))) : width;

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

  DeviceContext device(select_device(o.device));
  DeviceScene device_scene(device, bvh, pack_triangle_shading(scene, patches), pack_materials(scene));
  const CameraParams camera = pack_camera(scene.camera, width, height);
  std::unique_ptr<ProgressivePass> pass;
  std::uint64_t rounds = 0;
  std::optional<BundleGeometry> geometry;
  if (o.mode == "pt") {
    PathTracerSettings settings;
    settings.seed = o.seed;
    settings.max_depth = o.max_depth;
    pass = std::make_unique<PathTracerPass>(device, device_scene, camera, ray_epsilon_for(scene.bounds), settings);
    rounds = o.spp;
  } else {
    const BundleSize size = bundle_size(scene, patches);
    RayBundleSettings settings;
    settings.seed = o.seed;
    settings.bins = o.bins ? o.bins : default_bins(size);
    settings.warmup = o.warmup;
    settings.gouraud = o.gouraud;
    try {
      check_bundle_memory(device.info, size, settings.bins, std::size_t(width) * height);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    geometry = build_bundle_geometry(scene, patches);
    pass = std::make_unique<RayBundlePass>(device, device_scene, *geometry, camera, settings);
    rounds = o.iterations;
  }

  install_interrupt_handlers();
  std::fprintf(stderr, "bundlepath: rendering %s (%dx%d, %s, %zu triangles, %u patches) on %s\n", o.scene.c_str(), width,
               height, o.mode.c_str(), scene.triangles.size(), patches.patch_count, device.description().c_str());
  Accumulator accum(width, height);
  ProgressBar bar(o.mode);
  const double pixels = double(width) * height;
  const bool per_pixel = o.mode == "pt";
  RenderOutcome outcome = run_progressive(
      *pass, accum, RenderBudget{rounds, o.seconds}, stop_requested(), [&](const RenderProgress& p) {
        double secs = std::max(p.elapsed_seconds, 1e-9);
        bar.update(p.fraction, double(p.rounds_done) * (per_pixel ? pixels : 1.0) / secs, double(p.rays) / secs * 1e-6,
                   p.elapsed_seconds, per_pixel ? "samples/s" : "iterations/s");
      });
  bar.finish();

  ImageRGB image = accum.mean();
  std::filesystem::path prefix(o.out_prefix);
  if (prefix.has_parent_path()) std::filesystem::create_directories(prefix.parent_path());
  const std::string exr_path = o.out_prefix + ".exr", png_path = o.out_prefix + ".png";
  write_exr(exr_path, {{"", &image}});
  write_png(png_path, image, o.exposure);

  double mrays_per_second = outcome.seconds > 0 ? double(outcome.rays) / outcome.seconds * 1e-6 : 0.0;
  if (!o.stats_path.empty()) {
    nlohmann::json stats;
    stats["scene"] = o.scene;
    stats["device"] = device.description();
    stats["mode"] = o.mode;
    stats["width"] = width;
    stats["height"] = height;
    stats["spp"] = per_pixel ? outcome.rounds : 0;
    stats["seed"] = o.seed;
    stats["triangles"] = scene.triangles.size();
    stats["patches"] = patches.patch_count;
    stats["patch_size"] = patch_size;
    stats["load_seconds"] = load_seconds;
    stats["bvh_build_seconds"] = bvh_seconds;
    stats["kernel_build_seconds"] = pass->program().build_seconds;
    stats["kernel_from_cache"] = pass->program().from_cache;
    stats["render_seconds"] = outcome.seconds;
    stats["rays"] = outcome.rays;
    stats["mrays_per_second"] = mrays_per_second;
    stats["nan_or_inf_samples"] = outcome.nonfinite_samples;
    stats["interrupted"] = outcome.interrupted;
    if (auto* rb = dynamic_cast<RayBundlePass*>(pass.get())) {
      const double iterations = double(outcome.rounds) + o.warmup;
      stats["iterations"] = outcome.rounds;
      stats["warmup_iterations"] = o.warmup;
      stats["bins"] = rb->bins();
      stats["elements"] = geometry->elements.size();
      stats["fragments_per_iteration"] = iterations > 0 ? double(outcome.fragments) / iterations : 0.0;
      stats["ms_per_iteration"] = outcome.rounds ? outcome.seconds * 1e3 / iterations : 0.0;
      stats["fragments_per_second"] = outcome.seconds > 0 ? double(outcome.fragments) / outcome.seconds : 0.0;
    }
    for (const auto& [name, t] : pass->launcher().totals())
      stats["launches"][name] = {{"count", t.launches}, {"device_seconds", t.device_seconds}};
    write_json_file(o.stats_path, stats);
  }
  std::fprintf(stderr, "bundlepath: %s%llu %s at %dx%d in %.2f s (%.2f Mrays/s) -> %s, %s\n",
               outcome.interrupted ? "interrupted after " : "", static_cast<unsigned long long>(outcome.rounds),
               per_pixel ? "spp" : "iterations", width,
               height, outcome.seconds, mrays_per_second, exr_path.c_str(), png_path.c_str());
  if (outcome.nonfinite_samples)
    std::fprintf(stderr, "bundlepath: warning: %llu NaN/Inf samples were dropped\n",
                 static_cast<unsigned long long>(outcome.nonfinite_samples));
  return outcome.interrupted ? 130 : 0;
}

}  // namespace bp

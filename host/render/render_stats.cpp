#include "render/render_stats.h"

#include "render/render_outputs.h"
#include "render/render_state.h"

#include <cmath>
#include <map>

namespace bp {
namespace {

// Every estimator pass of the render (on every device), for build times and launch totals.
std::vector<const ProgressivePass*> estimator_passes(const RenderState& s) {
  std::vector<const ProgressivePass*> out;
  for (const auto& pt : s.pt) out.push_back(pt.get());
  if (s.rb) out.push_back(s.rb.get());
  return out;
}

void add_pass_stats(const RenderState& s, nlohmann::json& stats) {
  double build_seconds = 0.0;
  bool from_cache = true;
  std::map<std::string, LaunchTotals> launches;  // summed over the devices that ran the same kernel
  for (const ProgressivePass* part : estimator_passes(s)) {
    build_seconds += part->program().build_seconds;
    from_cache = from_cache && part->program().from_cache;
    for (const auto& [name, t] : part->launcher().totals()) {
      launches[name].launches += t.launches;
      launches[name].device_seconds += t.device_seconds;
    }
  }
  for (const auto& [name, t] : launches)
    stats["launches"][name] = {{"count", t.launches}, {"device_seconds", t.device_seconds}};
  stats["kernel_build_seconds"] = build_seconds;
  stats["kernel_from_cache"] = from_cache;
}

void add_combination_stats(const RenderState& s, nlohmann::json& stats) {
  const RenderSpec& o = s.spec;
  const RoundShape& shape = *s.shape;
  stats["weights"] = o.weights;
  if (s.weight_mode == BP_WEIGHTS_PRODUCT) stats["beta"] = o.beta;
  if (s.light_sampling && s.rb) stats["rb_light_rate"] = s.light_rate;
  if (s.light_sampling && s.rb) stats["eye_direct"] = s.eye_direct_shared ? "shared" : "pt";
  if (s.light_sampling && s.rb) stats["rb_sun"] = s.spec.rb_sun_own ? "own" : "chosen";
  // c; PT alone (c = ∞, which JSON has no number for): the string "inf" (Python's float() reads it).
  const nlohmann::json ratio = shape.pt_alone() ? nlohmann::json("inf") : nlohmann::json(shape.ratio());
  stats["ratio"] = ratio;
  if (s.probe) {
    const RatioProbe& probe = *s.probe;
    stats["ratio_auto"] = {{"chosen", ratio},
                           {"pt_seconds_per_spp", probe.pt_seconds_per_spp},
                           {"rb_seconds_per_iteration", probe.rb_seconds_per_iteration},
                           {"pt_time_share", probe.pt_time_share},
                           {"pt_variance_kept", std::isnan(probe.pt_variance_kept) ? nlohmann::json(nullptr)
                                                                                   : nlohmann::json(probe.pt_variance_kept)},
                           {"pt_variance_batches", probe.pt_variance_batches},
                           {"probe_pt_samples", probe.pt_samples},
                           {"probe_pt_size", std::to_string(probe.pt_image.width) + "x" +
                                                 std::to_string(probe.pt_image.height)},
                           {"probe_rb_iterations", probe.rb_iterations},
                           {"probe_seconds", probe.probe_seconds},
                           {"probe_first_launch_seconds", probe.first_launch_seconds},
                           {"rule", s.several_devices() ? "concurrent" : "time_share"}};
  } else if (ratio_is_auto(o)) {
    stats["ratio_auto"] = {{"chosen", ratio}, {"from_checkpoint", true}};
  }
  stats["rounds"] = s.outcome.rounds;
}

void add_ray_bundle_stats(const RenderState& s, const RenderResult& r, nlohmann::json& stats) {
  const RenderSpec& o = s.spec;
  const RenderOutcome& outcome = s.outcome;
  const Scene& scene = s.scene.scene;
  const double iterations = double(r.rb_iterations) + o.warmup;
  const std::size_t pixels = std::size_t(s.scene.width) * s.scene.height * s.views.size();  // every view's eye hits
  stats["iterations"] = r.rb_iterations;
  stats["warmup_iterations"] = o.warmup;
  stats["bins"] = s.rb->bins();
  stats["contact_depth"] = s.rb_settings.contact_depth_fraction;
  // The paper's weights gather every iteration whatever was asked (kernels/bundle.cl, eye_in_blocks).
  stats["rb_eye_gather"] =
      s.rb_settings.eye_blocks && s.rb_settings.weight_mode != BP_WEIGHTS_PAPER ? "blocks" : "every";
  stats["rb_directions"] = s.rb_settings.directions == DirectionSequence::independent ? "independent" : "stratified";
  stats["elements"] = s.geometry->elements.size();
  stats["fragments_per_iteration"] = iterations > 0 ? double(outcome.fragments) / iterations : 0.0;
  stats["ms_per_iteration"] = r.rb_iterations && !s.shape ? outcome.seconds * 1e3 / iterations : 0.0;
  stats["fragments_per_second"] = outcome.seconds > 0 ? double(outcome.fragments) / outcome.seconds : 0.0;
  stats["rb_device_bytes_estimate"] =
      estimate_bundle_memory(bundle_size(scene, s.scene.patches), s.rb->bins(), pixels, bundle_chains(s.rb_settings),
                             scene.has_shading_normals(), scene.has_textures());
  stats["rb_chains"] = bundle_chains(s.rb_settings);
}

// The first view's batches (every view's are the same rounds), per layer; a walkthrough's estimate is
// its worst frame's.
void add_error_estimate_stats(const RenderState& s, nlohmann::json& stats) {
  const ImageErrorEstimate& e = *s.first_view().error_estimate;
  stats["estimated_rel_mse"] = s.estimated_rel_mse;  // NaN (null) before two batches
  nlohmann::json levels = nlohmann::json::array(), layers = nlohmann::json::array();
  for (int j = 0; j < e.layers().front().levels(); ++j) levels.push_back({{"estimated_rel_mse", e.estimated_rel_mse(j)}});
  for (std::size_t l = 0; l < e.layers().size(); ++l) {
    const BatchMeansErrorEstimate& layer = e.layers()[l];
    const bool rb_layer = std::string(e.layer_name(l)) == "rb";
    nlohmann::json layer_levels = nlohmann::json::array();
    for (int j = 0; j < layer.levels(); ++j)
      layer_levels.push_back({{"batch_rounds", layer.batch_rounds(j)},
                              {"batches", layer.batches(j)},
                              {"estimated_rel_mse", e.layer_rel_mse(l, j)}});
    nlohmann::json out = {{"layer", e.layer_name(l)},
                          {"batch_rounds", layer.batch_rounds()},
                          {"batches", layer.batches()},
                          {"estimated_rel_mse", e.layer_rel_mse(l)},
                          {"levels", layer_levels}};
    if (rb_layer) out["batch_iterations"] = layer.batch_rounds() * (s.shape ? s.shape->rb_iterations : 1);
    layers.push_back(out);
  }
  stats["error_estimate"] = {{"degrees_of_freedom", e.degrees_of_freedom()}, {"levels", levels}, {"layers", layers}};
  // Part of estimated_rel_mse: RB's layer against PT's estimate of its share (null: no check).
  stats["error_estimate"]["rb_bias_rel_mse"] = e.rb_bias_rel_mse();
  const ImageErrorEstimate::RbBiasCheck check = e.rb_bias_check();  // what it was counted from (null: not yet)
  stats["error_estimate"]["rb_bias_check"] = {{"estimate", check.estimate},
                                              {"standard_error", check.standard_error},
                                              {"batches", check.batches}};
}

// --rb-level (image/rb_level.h): per channel, the factor on RB's layer and the two levels it weighs
// (corrected: one each; regional: one per region, row by row, with the regional error's weights as
// the image has them).
void add_rb_level_stats(const RenderState& s, nlohmann::json& stats) {
  if (!s.first_view().rb_level) {
    stats["rb_level"] = {{"mode", "own"}};
    return;
  }
  const RbLevel& l = *s.first_view().rb_level;
  const bool one = l.grid().count() == 1;
  const auto json3 = [&](const std::vector<std::array<double, 3>>& v) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& a : v) out.push_back(nlohmann::json::array({a[0], a[1], a[2]}));
    return one ? out[0] : out;
  };
  stats["rb_level"] = {{"mode", s.spec.rb_level},
                       {"regions", {l.grid().columns, l.grid().rows}},
                       {"factors", json3(l.factors(rb_region_weights(s.first_view())))},
                       {"rb", json3(l.rb_levels())},
                       {"rb_stderr", json3(l.rb_standard_errors())},
                       {"pt", json3(l.pt_levels())},
                       {"pt_stderr", json3(l.pt_standard_errors())},
                       {"batches", l.batches()}};
}

// The regional error (image/regional_error.h): per region, row by row, the image's mean luminance
// and its estimated relative standard error; with --reference, each region's relative error against
// the reference's and its z-score against the estimate.
void add_regional_error_stats(const RenderState& s, const RenderResult& r, nlohmann::json& stats) {
  const RenderView& view = s.first_view();
  const RegionalError& e = *view.regional_error;
  const RegionGrid& g = e.grid();
  const auto finite_or_null = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json means = nlohmann::json::array(), relative = nlohmann::json::array();
  const std::vector<double> mean = e.region_means(), rel = e.relative_standard_errors();
  for (std::size_t b = 0; b < g.count(); ++b) {
    means.push_back(finite_or_null(mean[b]));
    relative.push_back(finite_or_null(rel[b]));
  }
  double worst_se = NAN;
  for (double v : rel)
    if (std::isfinite(v) && !(v <= worst_se)) worst_se = v;
  nlohmann::json out = {{"regions", {g.columns, g.rows}},
                        {"degrees_of_freedom", e.degrees_of_freedom()},
                        {"mean_luminance", means},
                        {"relative_stderr", relative},
                        {"largest_relative_stderr", finite_or_null(worst_se)},
                        {"expected_worst_error", finite_or_null(view.expected_worst_region_error)},
                        {"rb_batch_correlation", finite_or_null(e.rb_batch_correlation())}};
  if (s.scene.reference && !r.layers.empty()) {
    const std::vector<double> image = g.sums(r.layers.front().second.rgb), ref = g.sums(s.scene.reference->rgb);
    nlohmann::json errors = nlohmann::json::array(), z = nlohmann::json::array();
    double worst = 0.0, worst_z = 0.0;
    for (std::size_t b = 0; b < g.count(); ++b) {
      const double yi = luminance(image[b * 3], image[b * 3 + 1], image[b * 3 + 2]);
      const double yr = luminance(ref[b * 3], ref[b * 3 + 1], ref[b * 3 + 2]);
      const double err = yr > 0.0 ? yi / yr - 1.0 : NAN;
      const double zb = std::isfinite(rel[b]) && rel[b] > 0.0 && yi > 0.0 ? (yi - yr) / (rel[b] * yi) : NAN;
      errors.push_back(finite_or_null(err));
      z.push_back(finite_or_null(zb));
      if (std::isfinite(err)) worst = std::max(worst, std::abs(err));
      if (std::isfinite(zb)) worst_z = std::max(worst_z, std::abs(zb));
    }
    out["reference"] = {{"relative_error", errors}, {"z", z}, {"worst_error", worst}, {"worst_z", worst_z}};
  }
  stats["regional_error"] = out;
}

nlohmann::json vector_json(const glm::vec3& v) { return {v.x, v.y, v.z}; }

// A walkthrough's frames: each one's files, camera and estimated relMSE (docs/design.md §8).
void add_frame_stats(const RenderState& s, const RenderResult& r, nlohmann::json& stats) {
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t k = 0; k < r.frames.size(); ++k) {
    const SceneCamera& camera = s.views[k].scene_camera;
    frames.push_back({{"index", k},
                      {"exr", r.frames[k].exr_path},
                      {"png", r.frames[k].png_path},
                      {"estimated_rel_mse", r.frames[k].estimated_rel_mse},
                      {"position", vector_json(camera.position)},
                      {"forward", vector_json(camera.forward)},
                      {"up", vector_json(camera.up)},
                      {"yfov", camera.yfov}});
  }
  stats["frames"] = frames;
  if (!r.video_path.empty()) stats["video"] = r.video_path;
}

}  // namespace

nlohmann::json render_stats(const RenderState& s, const RenderResult& r) {
  const RenderSpec& o = s.spec;
  const RenderOutcome& outcome = s.outcome;
  const DeviceScene& device_scene = s.devices.front()->scene;
  nlohmann::json stats;
  stats["scene"] = o.scene;
  std::string device;
  for (const auto& d : s.devices) device += (device.empty() ? "" : " + ") + d->context.description();
  stats["device"] = device;
  stats["devices"] = nlohmann::json::array();
  for (const DeviceWorkReport& d : r.devices)
    stats["devices"].push_back({{"index", d.index},
                                {"name", d.name},
                                {"pt_samples", d.pt_samples},
                                {"rb_iterations", d.rb_iterations},
                                {"busy_seconds", d.busy_seconds}});
  if (!r.device_failure.empty()) stats["device_failure"] = r.device_failure;
  stats["ranks"] = r.ranks;  // MPI ranks; "devices" are rank 0's
  stats["mode"] = o.mode;
  // --denoise: the image is OpenImageDenoise's; every error estimate here is of the raw image.
  stats["denoised"] = r.denoised;
  if (s.denoiser)
    stats["denoiser"] = {{"library", s.denoiser->library_path()},
                         {"version", s.denoiser->version()},
                         {"seconds", r.denoise_seconds},
                         {"error_estimates_are_of", "the raw image (the EXR's raw layers)"}};
  stats["width"] = s.scene.width;
  stats["height"] = s.scene.height;
  stats["spp"] = r.pt_samples;
  stats["seed"] = o.seed;
  stats["triangles"] = s.scene.scene.triangles.size();
  stats["patches"] = s.scene.patches.patch_count;
  stats["patch_size"] = s.scene.patch_size;
  stats["patch_seconds"] = s.scene.patch_seconds;
  if (patch_refinement_applies(o)) {
    stats["patch_refined_triangles"] = s.scene.refinement.refined_triangles;
    stats["patches_before_refinement"] = s.scene.refinement.patches_before;
    stats["patch_refine_budget_reached"] = s.scene.refinement.budget_reached;
  }
  if (o.patch_clusters) {
    stats["patch_clusters"] = s.scene.patches.clusters.clusters;
    stats["clustered_triangles"] = s.scene.patches.clusters.clustered_triangles;
  }
  stats["scene_device_bytes"] = device_scene.bytes;  // BVH, shading, materials, lights, light tree, receivers, textures
  stats["texture_device_bytes"] = device_scene.texture_bytes;  // texels, views, texcoords, patch means
  stats["environment_device_bytes"] = device_scene.environment_bytes;  // the environment map and its cdfs
  stats["load_seconds"] = s.scene.load_seconds;
  stats["bvh_build_seconds"] = s.scene.bvh_seconds;
  add_pass_stats(s, stats);
  stats["render_seconds"] = outcome.seconds;
  stats["rays"] = outcome.rays;
  stats["mrays_per_second"] = r.mrays_per_second;
  stats["nan_or_inf_samples"] = outcome.nonfinite_samples;
  stats["interrupted"] = outcome.interrupted;
  stats["light_sampling"] = s.light_sampling;
  stats["kernel_options"] = s.kernel_options;
  stats["lights"] = device_scene.light_count;
  stats["delta_light_share"] = device_scene.delta_light_share;
  if (s.light_sampling) stats["light_selection"] = o.light_selection;
  if (!o.resume_path.empty()) stats["resumed_from_rounds"] = s.first_round;
  if (!o.checkpoint_path.empty()) stats["checkpoint"] = o.checkpoint_path;
  if (s.shape) {
    add_combination_stats(s, stats);
    add_rb_level_stats(s, stats);
  }
  if (s.rb) add_ray_bundle_stats(s, r, stats);
  if (!r.reference_metrics.empty()) {
    nlohmann::json metrics;
    for (const auto& [key, m] : r.reference_metrics)
      metrics[key] = {{"rel_mse", m.rel_mse}, {"rmse", m.rmse}, {"mean_bias", m.mean_bias},
                      {"relative_bias", m.reference_mean != 0.0 ? m.mean_bias / m.reference_mean : 0.0}};
    stats["reference"] = {{"path", o.reference_path}, {"layers", metrics}};
  }
  add_error_estimate_stats(s, stats);
  add_regional_error_stats(s, r, stats);
  if (s.walkthrough()) add_frame_stats(s, r, stats);
  if (o.target_error > 0.0) stats["target_error"] = o.target_error;
  if (o.target_block_error > 0.0) stats["target_block_error"] = o.target_block_error;
  if (o.target_error > 0.0 || o.target_block_error > 0.0) stats["target_reached"] = outcome.target_reached;
  return stats;
}

}  // namespace bp

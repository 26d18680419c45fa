#include "passes/path_tracer.h"

#include <algorithm>

namespace bp {

namespace {
// The path tracer's parameters that come from the scene alone.
PathTraceParams scene_params(const DeviceScene& scene) {
  PathTraceParams params{};
  params.ray_epsilon = scene.ray_epsilon;
  params.shading_normals = scene.has_shading_normals;
  params.uv_slots = scene.uv_slots;
  params.environment_width = scene.environment_width;
  params.environment_height = scene.environment_height;
  return params;
}

// The argument list that pathtrace and first_hit_features share (kernels/pathtrace.cl); `out` is
// argument 8.
void set_scene_args(cl::Kernel& kernel, const DeviceScene& scene, const CameraParams& camera,
                    const PathTraceParams& params, const cl::Buffer& out) {
  set_args(kernel, scene.nodes, scene.triangles, scene.shading, scene.materials, scene.lights, scene.light_cdf, camera,
           params, out, scene.light_tree, scene.light_receivers, cl_uint(scene.light_selection), scene.shading_normals,
           scene.texture_views, scene.texels, scene.material_textures, scene.texcoords, scene.patch_materials,
           cl_uint(scene.alpha_masks), scene.environment, scene.tangents, scene.cluster_fans);
}
}  // namespace

PathTracerPass::PathTracerPass(const DeviceContext& device, const DeviceScene& scene, const CameraParams& camera,
                               const PathTracerSettings& settings, Accumulator& accum)
    : device_(device), accum_(accum), camera_(camera), launcher_(device) {
  params_ = scene_params(scene);
  params_.seed = settings.seed;
  params_.max_depth = settings.max_depth;
  params_.weight_mode = settings.weight_mode;
  params_.weight_ratio = settings.weight_ratio;
  params_.beta_heuristic = settings.beta_heuristic;
  params_.rb_light_rate = settings.rb_light_rate;
  params_.rb_sun_own_samples = settings.rb_sun_own ? 1u : 0u;
  params_.light_count = settings.light_sampling ? scene.light_count : 0u;
  params_.eye_direct_shared = settings.eye_direct_shared && settings.weight_mode == BP_WEIGHTS_PRODUCT ? 1u : 0u;
  params_.environment_light = settings.light_sampling ? scene.environment_light : BP_NO_LIGHT;
  program_ = build_program(device, "pathtrace.cl", settings.kernel_options);
  kernel_ = cl::Kernel(program_.program, "pathtrace");
  std::size_t pixels = std::size_t(camera.width) * camera.height;
  host_pixels_.resize(pixels);
  pixels_ = make_buffer(device, "pixel accumulators", CL_MEM_WRITE_ONLY, pixels * sizeof(PixelAccum));
  set_scene_args(kernel_, scene, camera_, params_, pixels_);
}

FirstHitFeatures render_first_hit_features(const DeviceContext& device, const DeviceScene& scene,
                                           const CameraParams& camera, const std::string& kernel_options,
                                           std::uint32_t samples_per_side) {
  PathTraceParams params = scene_params(scene);
  params.environment_light = BP_NO_LIGHT;
  params.samples_per_launch = samples_per_side;
  const BuiltProgram program = build_program(device, "pathtrace.cl", kernel_options);
  cl::Kernel kernel(program.program, "first_hit_features");
  const std::size_t pixels = std::size_t(camera.width) * camera.height;
  cl::Buffer out = make_buffer(device, "first-hit features", CL_MEM_WRITE_ONLY, pixels * 6 * sizeof(float));
  set_scene_args(kernel, scene, camera, params, out);
  Launcher launcher(device);
  launcher.launch("first_hit_features", kernel, pixels, 64);
  launcher.finish();
  std::vector<float> host(pixels * 6);
  device.queue.enqueueReadBuffer(out, CL_TRUE, 0, host.size() * sizeof(float), host.data());
  FirstHitFeatures f{ImageRGB(int(camera.width), int(camera.height)), ImageRGB(int(camera.width), int(camera.height))};
  for (std::size_t i = 0; i < pixels; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      f.albedo.rgb[i * 3 + c] = host[i * 6 + c];
      f.normal.rgb[i * 3 + c] = host[i * 6 + 3 + c];
    }
  return f;
}

std::uint32_t PathTracerPass::max_batch() const {
  return std::uint32_t(std::clamp<std::size_t>((std::size_t(1) << 20) / host_pixels_.size(), 1, 256));
}

BatchCounts PathTracerPass::run(std::uint64_t first, std::uint32_t count) {
  Accumulator& accum = accum_;
  params_.first_sample = std::uint32_t(first);
  params_.samples_per_launch = count;
  kernel_.setArg(7, params_);
  launcher_.launch("pathtrace", kernel_, host_pixels_.size(), 64);
  launcher_.finish();
  device_.queue.enqueueReadBuffer(pixels_, CL_TRUE, 0, host_pixels_.size() * sizeof(PixelAccum), host_pixels_.data());
  BatchCounts counts;
  for (std::size_t i = 0; i < host_pixels_.size(); ++i) {
    const PixelAccum& p = host_pixels_[i];
    for (int c = 0; c < 3; ++c) accum.sum[i * 3 + c] += double(p.weighted[c]);
    if (accum.keeps_raw())
      for (int c = 0; c < 3; ++c) accum.raw_sum[i * 3 + c] += double(p.raw[c]);
    counts.rays += p.rays;
    counts.nonfinite_samples += p.nonfinite_samples;
  }
  accum.samples_per_pixel += count;
  return counts;
}

}  // namespace bp

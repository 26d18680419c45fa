// Driver of the path-tracer megakernel (kernels/pathtrace.cl).
#pragma once
#include "device/device_scene.h"
#include "device/launcher.h"
#include "device/program_cache.h"
#include "image/accumulator.h"
#include "passes/pass.h"
#include <cstdint>
#include <string>

namespace bp {

struct PathTracerSettings {
  std::uint32_t seed = 0;
  std::uint32_t max_depth = 65536;            // safety cap; Russian roulette ends paths first
  std::uint32_t weight_mode = BP_WEIGHTS_NONE;
  float weight_ratio = 1.0f;                  // N2 / N1
  std::uint32_t beta_heuristic = BP_BETA_CLAMPED;  // product weights' per-vertex beta (BP_BETA_*)
  float rb_light_rate = 1.0f;                 // the ray bundles' light-sample rate, for the weights
  bool rb_sun_own = false;                    // RB's own samples of each sun (--rb-sun own), for the weights
  bool light_sampling = true;                 // next-event estimation (docs/design.md §3), where the scene has lights
  bool eye_direct_shared = false;             // combined: the eye vertex's direct light split with RB
  std::string kernel_options;                 // feature switches (device/kernel_features.h); empty: generic
};

class PathTracerPass : public ProgressivePass {
 public:
  // Adds its estimates into `accum` (sized like the camera's image).
  PathTracerPass(const DeviceContext& device, const DeviceScene& scene, const CameraParams& camera,
                 const PathTracerSettings& settings, Accumulator& accum);

  // Traces samples [first, first + count) of every pixel.
  BatchCounts run(std::uint64_t first, std::uint32_t count) override;
  // About 2^20 samples per launch.
  std::uint32_t max_batch() const override;

  const BuiltProgram& program() const override { return program_; }
  const Launcher& launcher() const override { return launcher_; }
  // The weight mode (BP_WEIGHTS_*) and N2 / N1 from the next sample on (--ratio auto sets them once,
  // after its probe).
  void set_weights(std::uint32_t mode, float n2_over_n1) {
    params_.weight_mode = mode;
    params_.weight_ratio = n2_over_n1;
  }
  void set_eye_direct_shared(bool shared) { params_.eye_direct_shared = shared ? 1u : 0u; }
  std::uint32_t pixel_width() const { return camera_.width; }
  std::uint32_t pixel_height() const { return camera_.height; }

 private:
  const DeviceContext& device_;
  Accumulator& accum_;
  CameraParams camera_;
  PathTraceParams params_{};
  BuiltProgram program_;
  cl::Kernel kernel_;
  cl::Buffer pixels_;
  std::vector<PixelAccum> host_pixels_;
  Launcher launcher_;
};

// What a denoiser reads beside the beauty (docs/design.md §13): each pixel's first-hit albedo and
// shading normal, seen through delta vertices (mirrors, glass), averaged over samples_per_side^2
// camera rays stratified over the pixel (the beauty's box filter). The same program as the path
// tracer's (kernels/pathtrace.cl, first_hit_features); deterministic.
struct FirstHitFeatures {
  ImageRGB albedo, normal;
};
FirstHitFeatures render_first_hit_features(const DeviceContext& device, const DeviceScene& scene,
                                           const CameraParams& camera, const std::string& kernel_options,
                                           std::uint32_t samples_per_side = 4);

}  // namespace bp

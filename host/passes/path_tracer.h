// Driver of the path-tracer megakernel (kernels/pathtrace.cl).
#pragma once
#include "device/device_scene.h"
#include "device/launcher.h"
#include "device/program_cache.h"
#include "image/accumulator.h"
#include <cstdint>

namespace bp {

struct PathTracerSettings {
  std::uint32_t seed = 0;
  std::uint32_t max_depth = 65536;            // safety cap; Russian roulette ends paths first
  std::uint32_t weight_mode = BP_WEIGHTS_NONE;
  float weight_ratio = 1.0f;                  // N2 / N1
};

struct BatchCounts {
  std::uint64_t rays = 0;
  std::uint64_t nonfinite_samples = 0;
};

class PathTracerPass {
 public:
  PathTracerPass(const DeviceContext& device, const DeviceScene& scene, const CameraParams& camera,
                 float ray_epsilon, const PathTracerSettings& settings);

  // Traces samples [first, first + count) of every pixel and adds them into accum.
  BatchCounts run(std::uint32_t first, std::uint32_t count, Accumulator& accum);

  const BuiltProgram& program() const { return program_; }
  const Launcher& launcher() const { return launcher_; }

 private:
  const DeviceContext& device_;
  CameraParams camera_;
  PathTraceParams params_{};
  BuiltProgram program_;
  cl::Kernel kernel_;
  cl::Buffer pixels_;
  std::vector<PixelAccum> host_pixels_;
  Launcher launcher_;
};

}  // namespace bp

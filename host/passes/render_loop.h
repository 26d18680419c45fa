// The render loop: runs batches of samples until the sample target, the time budget, or a stop
// request, and reports progress after each batch. The batch schedule depends only on the image
// size and the sample target, never on timing, so the same seed gives the same image.
#pragma once
#include "image/accumulator.h"
#include "passes/path_tracer.h"
#include <atomic>
#include <cstdint>
#include <functional>

namespace bp {

struct RenderBudget {
  std::uint64_t spp = 0;       // 0: no sample target
  double seconds = 0.0;        // 0: no time budget
};

struct RenderProgress {
  std::uint64_t spp_done = 0;
  std::uint64_t rays = 0;
  double elapsed_seconds = 0.0;
  double fraction = 0.0;       // of the budget (samples or time, whichever is nearer its end)
};

struct RenderOutcome {
  std::uint64_t spp = 0;
  std::uint64_t rays = 0;
  std::uint64_t nonfinite_samples = 0;
  double seconds = 0.0;
  bool interrupted = false;
};

// Samples per pixel of the batch that starts after `done` samples: a doubling ramp (so progress and
// --time react early) capped so one launch holds about 2^20 samples.
std::uint32_t batch_size(std::uint64_t done, std::uint64_t target_spp, std::size_t pixels);

RenderOutcome run_path_tracer(PathTracerPass& pass, Accumulator& accum, const RenderBudget& budget,
                              const std::atomic<bool>& stop_requested,
                              const std::function<void(const RenderProgress&)>& on_progress);

}  // namespace bp

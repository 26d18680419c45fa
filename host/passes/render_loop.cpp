#include "passes/render_loop.h"

#include <algorithm>
#include <chrono>

namespace bp {

std::uint32_t batch_size(std::uint64_t done, std::uint64_t target_spp, std::size_t pixels) {
  std::uint64_t cap = std::clamp<std::uint64_t>((1u << 20) / std::max<std::size_t>(pixels, 1), 1, 256);
  std::uint64_t ramp = std::max<std::uint64_t>(done, 1);  // 1, 1, 2, 4, 8, ... samples
  std::uint64_t size = std::min(cap, ramp);
  if (target_spp) size = std::min(size, target_spp - done);
  return std::uint32_t(size);
}

RenderOutcome run_path_tracer(PathTracerPass& pass, Accumulator& accum, const RenderBudget& budget,
                              const std::atomic<bool>& stop_requested,
                              const std::function<void(const RenderProgress&)>& on_progress) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  RenderOutcome out;
  const std::size_t pixels = std::size_t(accum.width) * accum.height;
  while (true) {
    double elapsed = std::chrono::duration<double>(clock::now() - start).count();
    if (budget.spp && out.spp >= budget.spp) break;
    if (budget.seconds > 0.0 && elapsed >= budget.seconds) break;
    if (stop_requested.load()) { out.interrupted = true; break; }
    std::uint32_t n = batch_size(out.spp, budget.spp, pixels);
    BatchCounts counts = pass.run(std::uint32_t(out.spp), n, accum);
    out.spp += n;
    out.rays += counts.rays;
    out.nonfinite_samples += counts.nonfinite_samples;
    if (on_progress) {
      RenderProgress p;
      p.spp_done = out.spp;
      p.rays = out.rays;
      p.elapsed_seconds = std::chrono::duration<double>(clock::now() - start).count();
      double by_spp = budget.spp ? double(out.spp) / double(budget.spp) : 0.0;
      double by_time = budget.seconds > 0.0 ? p.elapsed_seconds / budget.seconds : 0.0;
      p.fraction = std::min(1.0, std::max(by_spp, by_time));
      on_progress(p);
    }
  }
  out.seconds = std::chrono::duration<double>(clock::now() - start).count();
  return out;
}

}  // namespace bp

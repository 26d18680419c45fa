#include "passes/render_loop.h"

#include <algorithm>
#include <chrono>

namespace bp {

std::uint32_t batch_size(std::uint64_t done, std::uint64_t target, std::uint32_t max_batch) {
  std::uint64_t next;  // the first grid point after done
  if (done >= max_batch) {
    next = (done / max_batch + 1) * max_batch;
  } else {
    next = 1;
    while (next <= done) next *= 2;
    next = std::min<std::uint64_t>(next, max_batch);
  }
  std::uint64_t size = next - done;
  if (target) size = std::min(size, target - done);
  return std::uint32_t(size);
}

bool time_budget_spent(double elapsed, double budget, double next_batch_seconds) {
  return elapsed >= budget || elapsed + next_batch_seconds - budget > budget - elapsed;
}

RenderOutcome run_progressive(ProgressivePass& pass, const RenderBudget& budget,
                              const std::atomic<bool>& stop_requested,
                              const std::function<void(const RenderProgress&)>& on_progress,
                              std::uint64_t first_round) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  RenderOutcome out;
  out.rounds = first_round;
  double seconds_per_round = 0.0;  // the last batch's: the next batch's time is predicted from it
  while (true) {
    double elapsed = std::chrono::duration<double>(clock::now() - start).count();
    const std::uint32_t n = batch_size(out.rounds, budget.rounds, pass.max_batch());
    LoopStop stop = LoopStop::none;
    if (budget.rounds && out.rounds >= budget.rounds) stop = LoopStop::rounds;
    else if (budget.seconds > 0.0 && time_budget_spent(elapsed, budget.seconds, n * seconds_per_round))
      stop = LoopStop::time;
    else if (budget.target_reached && budget.target_reached()) stop = LoopStop::target_reached;
    else if (stop_requested.load()) stop = LoopStop::interrupted;
    if (budget.agree_stop) stop = budget.agree_stop(stop);
    if (stop != LoopStop::none) {
      out.target_reached = stop == LoopStop::target_reached;
      out.interrupted = stop == LoopStop::interrupted;
      break;
    }
    BatchCounts counts;
    const auto batch_start = clock::now();
    try {
      counts = pass.run(out.rounds, n);
    } catch (const PassFailure& e) {
      out.failure = e.what();
      break;
    }
    seconds_per_round = std::chrono::duration<double>(clock::now() - batch_start).count() / n;
    out.rounds += n;
    out.rays += counts.rays;
    out.fragments += counts.fragments;
    out.nonfinite_samples += counts.nonfinite_samples;
    if (on_progress) {
      RenderProgress p;
      p.rounds_done = out.rounds;
      p.rays = out.rays;
      p.elapsed_seconds = std::chrono::duration<double>(clock::now() - start).count();
      double by_rounds = budget.rounds ? double(out.rounds) / double(budget.rounds) : 0.0;
      double by_time = budget.seconds > 0.0 ? p.elapsed_seconds / budget.seconds : 0.0;
      p.fraction = std::min(1.0, std::max(by_rounds, by_time));
      on_progress(p);
    }
  }
  out.seconds = std::chrono::duration<double>(clock::now() - start).count();
  return out;
}

}  // namespace bp

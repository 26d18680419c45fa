// The render loop: runs batches of rounds (PT samples per pixel or RB iterations) until the round
// target, the time budget, or a stop request, and reports progress after each batch. The batch
// schedule depends only on the pass and the target, never on timing, so the same seed gives the
// same image.
#pragma once
#include "image/accumulator.h"
#include "passes/pass.h"
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

namespace bp {

// Why the render loop ends before a batch; of several, the larger wins (one process asks them in
// this order, from the last).
enum class LoopStop : int { none = 0, interrupted, target_reached, time, rounds };

struct RenderBudget {
  std::uint64_t rounds = 0;    // 0: no round target
  double seconds = 0.0;        // 0: no time budget
  // A further end, asked after each batch's progress report (--target-error: the estimated relMSE
  // is low enough); empty: none.
  std::function<bool()> target_reached = nullptr;
  // Several processes rendering one image (render/rank_pass.h): given this process's reason to stop
  // before a batch, returns the one they all agree on, so all stop at the same round; empty: none.
  std::function<LoopStop(LoopStop)> agree_stop = nullptr;
};

struct RenderProgress {
  std::uint64_t rounds_done = 0;
  std::uint64_t rays = 0;
  double elapsed_seconds = 0.0;
  double fraction = 0.0;       // of the budget (samples or time, whichever is nearer its end)
};

struct RenderOutcome {
  std::uint64_t rounds = 0;
  std::uint64_t rays = 0;
  std::uint64_t fragments = 0;
  std::uint64_t nonfinite_samples = 0;
  double seconds = 0.0;
  bool interrupted = false;
  bool target_reached = false;  // ended by budget.target_reached
  std::string failure;          // ended by a batch that failed (PassFailure's message); empty: none
};

// Rounds in the batch that starts after `done` rounds. Batches end on a fixed grid -- 1, 2, 4, ...,
// max_batch, then multiples of it -- whatever the target, so progress and --time react early, and a
// render stopped after any batch and resumed adds its sums in exactly the groups an uninterrupted
// render does (the same image, bit for bit). The last batch stops at the target.
std::uint32_t batch_size(std::uint64_t done, std::uint64_t target, std::uint32_t max_batch);

// --time: whether the render loop stops before a batch predicted to take next_batch_seconds, with
// elapsed of budget seconds gone: at the budget, or where that batch would end further past it than
// stopping now ends short of it. A render ends at the batch end nearest its budget, not at the first
// one past it (a batch can be a long round: --ratio auto's can take most of a short --time).
bool time_budget_spent(double elapsed, double budget, double next_batch_seconds);

// Runs from round first_round (0, or where a resumed render stopped) until the budget's round target
// (counted from 0), its seconds (counted in this run), its target_reached, a stop request, or a
// batch that failed.
RenderOutcome run_progressive(ProgressivePass& pass, const RenderBudget& budget,
                              const std::atomic<bool>& stop_requested,
                              const std::function<void(const RenderProgress&)>& on_progress,
                              std::uint64_t first_round = 0);

}  // namespace bp

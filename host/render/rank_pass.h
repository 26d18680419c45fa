// A render on several ranks (docs/design.md §8). Every rank runs the same render loop over the same
// deterministic batches of rounds; rank r renders the r-th of N equal slices of each batch
// (contiguous rounds, so PT's launches stay as long as one process's), into accumulators of its
// own, and after every batch their sums are added, in double, into root's render accumulators --
// which the error estimate, checkpoints and image files then read as on one process. The slices
// of a batch are the batch: PT's samples are a pure function of (seed, pixel, sample index), so
// N ranks give one process's image up to the order of float sums. RB runs a chain of its own on
// every rank (rank_chain_seed), over its slices' iterations.
#pragma once
#include "image/accumulator.h"
#include "passes/pass.h"
#include "render/ranks.h"

#include <cstdint>
#include <vector>

namespace bp {

// RB's seed on rank r: the render's on rank 0 (so one rank renders what one process does), and a
// different one on every other rank (its own chain: directions, light samples, eye jitter).
std::uint32_t rank_chain_seed(std::uint32_t seed, int rank);

// Rank r's rounds [first, end) of the batch [batch_first, batch_first + count): the r-th of N slices
// that differ by at most one round.
struct RoundSlice {
  std::uint64_t first = 0, end = 0;
};
RoundSlice rank_slice(std::uint64_t batch_first, std::uint32_t count, int rank, int ranks);

// One estimator's accumulators: what this rank's pass adds a batch into, and the render's, which
// root's receive the batch of every rank.
struct RankSums {
  Accumulator* rank = nullptr;
  Accumulator* render = nullptr;
};

class RankPass : public ProgressivePass {
 public:
  RankPass(ProgressivePass& pass, const Ranks& ranks, std::vector<RankSums> sums);
  // This rank's slice of the batch, then the sums (and the counts, rays and fragments) of every
  // rank into root's. Throws PassFailure, naming the rank, on every rank where one rank's pass
  // failed: then no rank's part of the batch is added.
  BatchCounts run(std::uint64_t first, std::uint32_t count) override;
  // Each rank's slice as long as one process's batch.
  std::uint32_t max_batch() const override;
  const Launcher& launcher() const override { return pass_.launcher(); }
  const BuiltProgram& program() const override { return pass_.program(); }
  std::vector<const ProgressivePass*> parts() const override { return pass_.parts(); }
  std::uint64_t rank_rounds() const { return rank_rounds_; }  // this rank's rounds in this run

 private:
  ProgressivePass& pass_;
  const Ranks& ranks_;
  std::vector<RankSums> sums_;
  std::uint64_t rank_rounds_ = 0;
};

}  // namespace bp

// Several ranks (docs/design.md §8): how a batch is shared out, each rank's RB chain seed, the render
// loop's agreed stop, and one process's Ranks. Two real ranks: tests/e2e/test_ranks.cpp.
#include "passes/render_loop.h"
#include "render/rank_pass.h"
#include "render/ranks.h"

#include <gtest/gtest.h>
#include <set>
#include <stdexcept>

namespace bp {
namespace {

TEST(RankSlices, SlicesOfABatchAreTheBatchInOrderAndNearlyEqual) {
  for (int ranks = 1; ranks <= 5; ++ranks)
    for (std::uint32_t count : {0u, 1u, 2u, 7u, 64u, 513u}) {
      const std::uint64_t first = 1000;
      std::uint64_t next = first, smallest = ~0ull, largest = 0;
      for (int r = 0; r < ranks; ++r) {
        const RoundSlice s = rank_slice(first, count, r, ranks);
        EXPECT_EQ(s.first, next) << ranks << " ranks, " << count << " rounds, rank " << r;
        EXPECT_GE(s.end, s.first);
        smallest = std::min(smallest, s.end - s.first);
        largest = std::max(largest, s.end - s.first);
        next = s.end;
      }
      EXPECT_EQ(next, first + count) << ranks << " ranks, " << count << " rounds";
      EXPECT_LE(largest - smallest, 1u) << ranks << " ranks, " << count << " rounds";
    }
}

TEST(RankChainSeed, RankZeroKeepsTheSeedAndEveryOtherRankGetsItsOwn) {
  for (std::uint32_t seed : {0u, 1u, 7u, 0xffffffffu}) {
    EXPECT_EQ(rank_chain_seed(seed, 0), seed);
    std::set<std::uint32_t> seen{seed};
    for (int rank = 1; rank < 256; ++rank) EXPECT_TRUE(seen.insert(rank_chain_seed(seed, rank)).second) << rank;
  }
  // Neighbouring seeds on one rank do not give neighbouring chain seeds.
  EXPECT_NE(rank_chain_seed(7, 1) + 1, rank_chain_seed(8, 1));
}

TEST(OneRank, CollectivesKeepItsValues) {
  const Ranks one;
  EXPECT_EQ(one.size(), 1);
  EXPECT_TRUE(one.root());
  std::vector<double> sums{1.5, 2.5};
  one.sum_to_root(sums);
  EXPECT_EQ(sums, (std::vector<double>{1.5, 2.5}));
  EXPECT_EQ(one.max_over_ranks(3), 3);
  int value = 5;
  one.broadcast(value);
  EXPECT_EQ(value, 5);
  EXPECT_EQ(one.first_failure(""), "");
  EXPECT_EQ(one.first_failure("lost"), "lost");
}

// Counts the rounds it is asked for; nothing else of a pass is used by the render loop.
class CountingPass : public ProgressivePass {
 public:
  BatchCounts run(std::uint64_t first, std::uint32_t count) override {
    rounds += count;
    return {};
  }
  std::uint32_t max_batch() const override { return 4; }
  const Launcher& launcher() const override { throw std::logic_error("not a device pass"); }
  const BuiltProgram& program() const override { throw std::logic_error("not a device pass"); }
  std::uint64_t rounds = 0;
};

TEST(RenderLoop, AgreedStopOverridesThisProcesssReason) {
  CountingPass pass;
  std::atomic<bool> stop{false};
  int asked = 0;
  RenderBudget budget{100, 0.0, {}};
  // Another process was interrupted before the third batch: this one stops there too.
  budget.agree_stop = [&](LoopStop mine) {
    EXPECT_EQ(mine, LoopStop::none);
    return ++asked == 3 ? LoopStop::interrupted : mine;
  };
  const RenderOutcome out = run_progressive(pass, budget, stop, nullptr);
  EXPECT_TRUE(out.interrupted);
  EXPECT_EQ(out.rounds, 2u);  // batches of 1 and 1
  EXPECT_EQ(pass.rounds, 2u);

  // Root's time is up: every process stops with that reason, whatever its own.
  CountingPass other;
  budget.agree_stop = [&](LoopStop mine) { return mine == LoopStop::none ? LoopStop::time : mine; };
  const RenderOutcome timed = run_progressive(other, budget, stop, nullptr);
  EXPECT_FALSE(timed.interrupted);
  EXPECT_EQ(timed.rounds, 0u);
}

}  // namespace
}  // namespace bp

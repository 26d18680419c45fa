// A walkthrough's path tracing (docs/design.md §8): every view has a pass of its own, and a round is the
// same samples of every view. PT shares no work between views; only ray bundles do (ray_bundles.h).
#pragma once
#include "passes/pass.h"

#include <vector>

namespace bp {

class EachViewPass : public ProgressivePass {
 public:
  explicit EachViewPass(std::vector<ProgressivePass*> views) : views_(std::move(views)) {}
  // Rounds [first, first + count) of each view, in view order.
  BatchCounts run(std::uint64_t first, std::uint32_t count) override;
  std::uint32_t max_batch() const override;
  const Launcher& launcher() const override { return views_.front()->launcher(); }
  const BuiltProgram& program() const override { return views_.front()->program(); }
  std::vector<const ProgressivePass*> parts() const override;

 private:
  std::vector<ProgressivePass*> views_;
};

}  // namespace bp

// Checkpoints (--checkpoint, --resume): everything a render needs to continue exactly where it
// stopped -- the accumulators, the ray-bundle state, the round count -- and the options that made
// it, so a resume with different options is refused rather than mixed.
#pragma once
#include "image/accumulator.h"
#include "image/error_estimate.h"
#include "image/rb_level.h"
#include "image/regional_error.h"
#include "passes/ray_bundles.h"
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bp {

struct Checkpoint {
  std::string options;           // canonical description of everything that shapes the image
  std::uint64_t rounds = 0;      // rounds completed (a batch boundary)
  double render_seconds = 0.0;   // rendering time spent so far, over all runs
  std::optional<Accumulator> pt, rb;
  std::optional<RayBundlePass::State> rb_state;
  // The error estimate's batch statistics (docs/design.md §9), one per estimator's layer (PT's, RB's;
  // image/error_estimate.h), the check's, and --rb-level consistent's two (PT's u and d). Empty in
  // the oldest checkpoints; one, of the layers' sum, in those of formats 02 and 03. A resumed render
  // whose layers they do not fit starts its estimate afresh.
  std::vector<BatchMeansErrorEstimate::State> error_estimate;
  // The RB level's batch statistics (--rb-level corrected, image/rb_level.h); absent before format 03.
  std::optional<RbLevel::State> rb_level;
  // The regional error's batch statistics (image/regional_error.h); absent before format 05.
  std::optional<RegionalError::State> regional_error;
  // The check of RB's layer against PT's estimate of its share (ImageErrorEstimate::rb_bias_check);
  // zero before format 06.
  ImageErrorEstimate::RbBiasSums rb_bias_sums;
  // A walkthrough's views after the first (docs/design.md §8; the first is pt, rb, error_estimate above):
  // each one's accumulators and error estimate. The ray-bundle state is the views' one chain.
  struct View {
    std::optional<Accumulator> pt, rb;
    std::vector<BatchMeansErrorEstimate::State> error_estimate;
    std::optional<RbLevel::State> rb_level;
    std::optional<RegionalError::State> regional_error;
    ImageErrorEstimate::RbBiasSums rb_bias_sums;
  };
  std::vector<View> further_views;
};

// Binary, written atomically (temporary file, then rename). Throws std::runtime_error naming the file.
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Throws std::runtime_error naming the file if it is missing, not a checkpoint, or truncated.
Checkpoint read_checkpoint(const std::string& path);

}  // namespace bp

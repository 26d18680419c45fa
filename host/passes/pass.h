// What the render loop needs of an estimator: run a batch of rounds (PT samples per pixel, or RB
// iterations) and add their estimates into the accumulator.
#pragma once
#include "device/launcher.h"
#include "device/program_cache.h"
#include "image/accumulator.h"
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace bp {

struct BatchCounts {
  std::uint64_t rays = 0;               // rays traced (camera, bounce and primary-hit rays)
  std::uint64_t fragments = 0;          // transillumination-buffer fragments (ray bundles)
  std::uint64_t nonfinite_samples = 0;  // samples dropped because they were NaN or Inf
  BatchCounts& operator+=(const BatchCounts& c) {
    rays += c.rays;
    fragments += c.fragments;
    nonfinite_samples += c.nonfinite_samples;
    return *this;
  }
};

// A batch that did not complete (a device failed during it): nothing of it was added, and the
// render ends with the rounds before it. The message names the device.
class PassFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ProgressivePass {
 public:
  virtual ~ProgressivePass() = default;
  // Rounds [first, first + count): adds their estimates into the pass's accumulator(s). Throws
  // PassFailure if it could add none of them.
  virtual BatchCounts run(std::uint64_t first, std::uint32_t count) = 0;
  // Most rounds in one batch (so a batch stays a fraction of a second).
  virtual std::uint32_t max_batch() const = 0;
  virtual const Launcher& launcher() const = 0;
  virtual const BuiltProgram& program() const = 0;
  // The estimators this pass drives (itself, or the two of a combination), for the stats.
  virtual std::vector<const ProgressivePass*> parts() const { return {this}; }
};

}  // namespace bp

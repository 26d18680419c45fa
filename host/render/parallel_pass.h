// A render on several devices (docs/design.md §8): each batch of rounds is shared out to the devices'
// passes, which run at the same time, each on a host thread of its own and into an accumulator of
// its own; once every device has finished the batch, their sums are added to the render's
// accumulators. RB runs on one device (its iterations are one chain); PT is split over its devices
// by sample index, in proportion to each one's measured speed (work_balancer-style: never guessed),
// measured after an untimed first launch (which builds PoCL's work-group code, seconds when cold).
#pragma once
#include "image/accumulator.h"
#include "passes/combined.h"
#include "passes/path_tracer.h"
#include "passes/ray_bundles.h"

#include <optional>
#include <string>
#include <vector>

namespace bp {

// One device's part: its pass (PT or RB) and the accumulator that pass adds into.
struct DeviceLane {
  int device_index = 0;      // as `bundlepath devices` lists it
  std::string device_name;
  PathTracerPass* pt = nullptr;
  RayBundlePass* rb = nullptr;
  Accumulator* accum = nullptr;
  std::uint64_t pt_samples = 0, rb_iterations = 0;  // done in this run
  double busy_seconds = 0.0;                        // its pass's time in this run
  double sampling_seconds = 0.0;                    // of which PT's counted samples (its speed)
  std::uint64_t batches = 0;                        // batches it took part in
};

// --ratio auto with PT and RB on different devices: a round takes max(N1 t_PT, N2 t_RB) rather than
// their sum, and neither device idles when N1 t_PT = N2 t_RB, i.e. c = t_RB / t_PT (t_PT: one
// sample per pixel on the PT devices together). c is the nearer (in log) of the two integers, or
// inverse integers, around it, clamped to [1/1024, 64] as auto_ratio_shape clamps.
RoundShape concurrent_ratio_shape(double pt_seconds_per_spp, double rb_seconds_per_iteration);

// Test hook: BUNDLEPATH_TEST_FAIL_DEVICE=INDEX:BATCH makes device INDEX fail (as a lost device
// would) in its batch number BATCH (from 0) of a render on several devices.
constexpr const char* kFailDeviceVariable = "BUNDLEPATH_TEST_FAIL_DEVICE";
// Test hook: BUNDLEPATH_TEST_SLOW_DEVICE=INDEX:FACTOR makes device INDEX take FACTOR times as long
// (it waits FACTOR - 1 times its work after each batch): two PoCL devices share the same cores, so
// on a loaded machine "basic" and "pthread" can run at about the same speed.
constexpr const char* kSlowDeviceVariable = "BUNDLEPATH_TEST_SLOW_DEVICE";

class ParallelPass : public ProgressivePass {
 public:
  // shape: the combination's round; none: a round is one PT sample per pixel (--mode pt) or one RB
  // iteration (--mode rb). The totals are the render's accumulators.
  ParallelPass(std::vector<DeviceLane> lanes, std::optional<RoundShape> shape, Accumulator& pt_total,
               Accumulator& rb_total);
  // Throws PassFailure naming the device when one fails; then nothing of the batch is added.
  BatchCounts run(std::uint64_t first, std::uint32_t count) override;
  std::uint32_t max_batch() const override;
  const Launcher& launcher() const override;
  const BuiltProgram& program() const override;
  std::vector<const ProgressivePass*> parts() const override;
  const std::vector<DeviceLane>& lanes() const { return lanes_; }

 private:
  // Each PT lane's samples [first, end) of the batch's PT samples, in proportion to its speed.
  std::vector<std::uint64_t> pt_split(std::uint64_t first, std::uint64_t end) const;
  void run_lane(DeviceLane& lane, std::uint64_t first, std::uint64_t end, BatchCounts& counts);

  std::vector<DeviceLane> lanes_;
  std::optional<RoundShape> shape_;
  Accumulator& pt_total_;
  Accumulator& rb_total_;
  int fail_device_ = -1;
  std::uint64_t fail_batch_ = 0;
  int slow_device_ = -1;
  double slow_factor_ = 1.0;
};

}  // namespace bp

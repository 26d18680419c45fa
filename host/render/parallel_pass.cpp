#include "render/parallel_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace bp {

RoundShape concurrent_ratio_shape(double pt_seconds_per_spp, double rb_seconds_per_iteration) {
  const double t_pt = std::max(pt_seconds_per_spp, 1e-9), t_rb = std::max(rb_seconds_per_iteration, 1e-9);
  const double c = std::clamp(t_rb / t_pt, 1.0 / 1024.0, 64.0);
  // An integer N1 (c >= 1) or 1 / N2 (c < 1): of the two around c, the one nearer in log.
  const double n = c >= 1.0 ? c : 1.0 / c;
  const double below = std::max(1.0, std::floor(n)), above = std::ceil(n);
  const double chosen = std::log(n / below) <= std::log(above / n) ? below : above;
  return round_shape(c >= 1.0 ? chosen : 1.0 / chosen);
}

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string lane_label(const DeviceLane& lane) {
  return "device [" + std::to_string(lane.device_index) + "] " + lane.device_name;
}
}  // namespace

ParallelPass::ParallelPass(std::vector<DeviceLane> lanes, std::optional<RoundShape> shape, Accumulator& pt_total,
                           Accumulator& rb_total)
    : lanes_(std::move(lanes)), shape_(shape), pt_total_(pt_total), rb_total_(rb_total) {
  if (const char* hook = std::getenv(kFailDeviceVariable)) {
    unsigned long long batch = 0;
    if (std::sscanf(hook, "%d:%llu", &fail_device_, &batch) >= 1) fail_batch_ = batch;
  }
  if (const char* hook = std::getenv(kSlowDeviceVariable))
    if (std::sscanf(hook, "%d:%lf", &slow_device_, &slow_factor_) != 2) slow_device_ = -1;
}

std::vector<std::uint64_t> ParallelPass::pt_split(std::uint64_t first, std::uint64_t end) const {
  std::vector<double> speed;  // samples per pixel per second so far; equal until every lane has run
  bool measured = true;
  for (const DeviceLane& lane : lanes_)
    if (lane.pt) {
      speed.push_back(lane.sampling_seconds > 0.0 ? double(lane.pt_samples) / lane.sampling_seconds : 0.0);
      measured = measured && lane.pt_samples > 0;
    }
  if (!measured) std::fill(speed.begin(), speed.end(), 1.0);
  double total = 0.0;
  for (double v : speed) total += v;
  std::vector<std::uint64_t> bounds{first};
  double cumulative = 0.0;
  for (std::size_t k = 0; k + 1 < speed.size(); ++k) {
    cumulative += speed[k];
    bounds.push_back(first + std::uint64_t(std::llround(double(end - first) * cumulative / total)));
  }
  bounds.push_back(end);
  return bounds;
}

void ParallelPass::run_lane(DeviceLane& lane, std::uint64_t first, std::uint64_t end, BatchCounts& counts) {
  const auto start = std::chrono::steady_clock::now();
  lane.accum->clear();
  if (lane.device_index == fail_device_ && lane.batches == fail_batch_)
    throw DeviceError("simulated failure (" + std::string(kFailDeviceVariable) + ")");
  auto sampling = std::chrono::steady_clock::now();
  if (lane.pt) {  // launches that end on multiples of max_batch, as CombinedPass launches them
    if (lane.batches == 0) {  // no sample: pays the first launch outside the speed
      lane.pt->run(0, 0);
      sampling = std::chrono::steady_clock::now();
    }
    const std::uint64_t pt_max = std::max<std::uint32_t>(1, lane.pt->max_batch());
    for (std::uint64_t s = first; s < end;) {
      const std::uint64_t next = std::min(end, (s / pt_max + 1) * pt_max);
      counts += lane.pt->run(s, std::uint32_t(next - s));
      s = next;
    }
  } else if (end > first) {
    counts += lane.rb->run(first, std::uint32_t(end - first));
  }
  if (lane.device_index == slow_device_)
    std::this_thread::sleep_for(std::chrono::duration<double>((slow_factor_ - 1.0) * seconds_since(sampling)));
  if (lane.pt) lane.sampling_seconds += seconds_since(sampling);
  lane.busy_seconds += seconds_since(start);
}

BatchCounts ParallelPass::run(std::uint64_t first, std::uint32_t count) {
  const std::uint64_t n1 = shape_ ? shape_->pt_samples : 1, n2 = shape_ ? shape_->rb_iterations : 1;
  const std::vector<std::uint64_t> pt_bounds = pt_split(first * n1, (first + count) * n1);
  struct Work {
    std::uint64_t first = 0, end = 0;
    BatchCounts counts;
    std::string error;
  };
  std::vector<Work> work(lanes_.size());
  std::size_t pt_index = 0;
  for (std::size_t i = 0; i < lanes_.size(); ++i) {
    if (lanes_[i].pt) {
      work[i].first = pt_bounds[pt_index];
      work[i].end = pt_bounds[pt_index + 1];
      ++pt_index;
    } else {
      work[i].first = first * n2;
      work[i].end = (first + count) * n2;
    }
  }
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < lanes_.size(); ++i)
    threads.emplace_back([&, i] {
      try {
        run_lane(lanes_[i], work[i].first, work[i].end, work[i].counts);
      } catch (const cl::Error& e) {
        work[i].error = std::string(e.what()) + ": " + cl_error_name(e.err());
      } catch (const std::exception& e) {
        work[i].error = e.what();
      } catch (...) {
        work[i].error = "unknown error";
      }
    });
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < lanes_.size(); ++i)
    if (!work[i].error.empty()) throw PassFailure(lane_label(lanes_[i]) + " failed: " + work[i].error);
  BatchCounts total;
  for (std::size_t i = 0; i < lanes_.size(); ++i) {
    DeviceLane& lane = lanes_[i];
    (lane.pt ? pt_total_ : rb_total_).add(*lane.accum);
    total += work[i].counts;
    (lane.pt ? lane.pt_samples : lane.rb_iterations) += work[i].end - work[i].first;
    ++lane.batches;
  }
  return total;
}

std::uint32_t ParallelPass::max_batch() const {
  std::uint64_t pt_lanes = 0, pt_max = 0, rb_max = 0;
  for (const DeviceLane& lane : lanes_) {
    if (lane.pt) {
      ++pt_lanes;
      pt_max = lane.pt->max_batch();
    } else {
      rb_max = lane.rb->max_batch();
    }
  }
  const std::uint64_t n1 = shape_ ? shape_->pt_samples : 1, n2 = shape_ ? shape_->rb_iterations : 1;
  std::uint64_t batch = ~std::uint64_t(0);
  if (pt_lanes && n1) batch = std::min(batch, pt_max * pt_lanes / n1);
  if (rb_max) batch = std::min(batch, rb_max / n2);
  return std::uint32_t(std::clamp<std::uint64_t>(batch, 1, 1u << 30));
}

const Launcher& ParallelPass::launcher() const {
  return lanes_.front().pt ? lanes_.front().pt->launcher() : lanes_.front().rb->launcher();
}

const BuiltProgram& ParallelPass::program() const {
  return lanes_.front().pt ? lanes_.front().pt->program() : lanes_.front().rb->program();
}

std::vector<const ProgressivePass*> ParallelPass::parts() const {
  std::vector<const ProgressivePass*> out;
  for (const DeviceLane& lane : lanes_) out.push_back(lane.pt ? static_cast<const ProgressivePass*>(lane.pt) : lane.rb);
  return out;
}

}  // namespace bp

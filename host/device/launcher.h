// Named kernel launches: every launch has a name used in errors and in the stats.
#pragma once
#include "device/device_context.h"
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace bp {

struct LaunchTotals {
  std::uint64_t launches = 0;
  double device_seconds = 0.0;  // from OpenCL profiling events
};

class Launcher {
 public:
  explicit Launcher(const DeviceContext& device) : device_(device) {}

  // 1-D launch; global is rounded up to a multiple of local (always explicit: PoCL picks
  // work-groups of 1 for odd sizes otherwise, docs/design.md §7). Kernels check their own bounds.
  void launch(const std::string& name, const cl::Kernel& kernel, std::size_t global, std::size_t local);

  // Waits for every launch and adds their profiled times to totals().
  void finish();

  const std::map<std::string, LaunchTotals>& totals() const { return totals_; }

 private:
  const DeviceContext& device_;
  std::vector<std::pair<std::string, cl::Event>> pending_;
  std::map<std::string, LaunchTotals> totals_;
};

// Sets a kernel's arguments in order: set_args(kernel, a0, a1, ...).
template <class... Args>
void set_args(cl::Kernel& kernel, const Args&... args) {
  cl_uint index = 0;
  (kernel.setArg(index++, args), ...);
}

// A device buffer of `count` elements of T initialised from host data (or zero-sized data:
// one element is allocated, since OpenCL has no empty buffers). `name` goes into errors.
cl::Buffer make_buffer(const DeviceContext& device, const std::string& name, cl_mem_flags flags,
                       std::size_t bytes, const void* host_data = nullptr);

template <class T>
cl::Buffer upload_buffer(const DeviceContext& device, const std::string& name, const std::vector<T>& data) {
  return make_buffer(device, name, CL_MEM_READ_ONLY, data.size() * sizeof(T), data.empty() ? nullptr : data.data());
}

}  // namespace bp

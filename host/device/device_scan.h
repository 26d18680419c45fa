// Exclusive prefix sum on the device (kernels/scan.cl, compiled into the caller's program).
#pragma once
#include "device/launcher.h"

namespace bp {

class DeviceScan {
 public:
  DeviceScan(const DeviceContext& device, const cl::Program& program);
  // offsets[i] = sum of values[0..i) for i <= n (offsets holds n + 1 entries). Enqueued only.
  void exclusive(Launcher& launcher, const cl::Buffer& values, std::size_t n, const cl::Buffer& offsets);

 private:
  std::size_t chunk_for(std::size_t n) const;
  const DeviceContext& device_;
  cl::Kernel totals_kernel_, scan_totals_kernel_, chunks_kernel_;
  cl::Buffer totals_;
  std::size_t max_chunks_;
};

}  // namespace bp

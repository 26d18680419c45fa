#include "device/device_scan.h"

#include <algorithm>

namespace bp {

namespace {
constexpr std::size_t kMaxChunks = 4096;  // enough parallel work for any device; one thread scans them
}

DeviceScan::DeviceScan(const DeviceContext& device, const cl::Program& program)
    : device_(device),
      totals_kernel_(program, "scan_chunk_totals"),
      scan_totals_kernel_(program, "scan_totals"),
      chunks_kernel_(program, "scan_chunks"),
      max_chunks_(kMaxChunks) {
  totals_ = make_buffer(device, "scan chunk totals", CL_MEM_READ_WRITE, (kMaxChunks + 1) * sizeof(cl_uint));
}

std::size_t DeviceScan::chunk_for(std::size_t n) const {
  return std::max<std::size_t>(256, (n + max_chunks_ - 1) / max_chunks_);
}

void DeviceScan::exclusive(Launcher& launcher, const cl::Buffer& values, std::size_t n, const cl::Buffer& offsets) {
  if (n == 0) {
    device_.queue.enqueueFillBuffer(offsets, cl_uint(0), 0, sizeof(cl_uint));
    return;
  }
  const cl_uint count = cl_uint(n), chunk = cl_uint(chunk_for(n));
  const cl_uint chunks = cl_uint((n + chunk - 1) / chunk);
  set_args(totals_kernel_, values, count, chunk, totals_);
  set_args(scan_totals_kernel_, totals_, chunks);
  set_args(chunks_kernel_, values, count, chunk, totals_, offsets);
  launcher.launch("scan_chunk_totals", totals_kernel_, chunks, 64);
  launcher.launch("scan_totals", scan_totals_kernel_, 1, 1);
  launcher.launch("scan_chunks", chunks_kernel_, chunks, 64);
}

}  // namespace bp

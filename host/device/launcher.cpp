#include "device/launcher.h"

namespace bp {

void Launcher::launch(const std::string& name, const cl::Kernel& kernel, std::size_t global, std::size_t local) {
  std::size_t rounded = (global + local - 1) / local * local;
  cl::Event event;
  try {
    device_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(rounded), cl::NDRange(local), nullptr,
                                       &event);
  } catch (const cl::Error& e) {
    throw DeviceError("launch of kernel '" + name + "' (" + std::to_string(rounded) + " work-items in groups of " +
                      std::to_string(local) + ") failed on " + device_.info.device_name + ": " +
                      cl_error_name(e.err()));
  }
  pending_.emplace_back(name, event);
}

void Launcher::finish() {
  try {
    device_.queue.finish();
  } catch (const cl::Error& e) {
    std::string names;
    for (auto& [name, event] : pending_) names += (names.empty() ? "" : ", ") + name;
    throw DeviceError("kernel(s) " + names + " failed on " + device_.info.device_name + ": " +
                      cl_error_name(e.err()));
  }
  for (auto& [name, event] : pending_) {
    LaunchTotals& t = totals_[name];
    ++t.launches;
    try {
      cl_ulong begin = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
      cl_ulong end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
      t.device_seconds += double(end - begin) * 1e-9;
    } catch (const cl::Error&) {
      // profiling unavailable on this device: count the launch, not its time
    }
  }
  pending_.clear();
}

cl::Buffer make_buffer(const DeviceContext& device, const std::string& name, cl_mem_flags flags,
                       std::size_t bytes, const void* host_data) {
  std::size_t size = bytes == 0 ? 16 : bytes;
  try {
    if (host_data) return cl::Buffer(device.context, flags | CL_MEM_COPY_HOST_PTR, size, const_cast<void*>(host_data));
    return cl::Buffer(device.context, flags, size);
  } catch (const cl::Error& e) {
    throw DeviceError("cannot allocate device buffer '" + name + "' (" + std::to_string(size >> 20) + " MiB) on " +
                      device.info.device_name + ": " + cl_error_name(e.err()));
  }
}

}  // namespace bp

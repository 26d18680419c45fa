// Device choice and the context/queue the passes run on.
#pragma once
#include "device/opencl.h"
#include <string>
#include <vector>

namespace bp {

struct DeviceInfo {
  int index;                 // global index across platforms, as `bundlepath devices` prints it
  cl::Platform platform;
  cl::Device device;
  std::string platform_name, device_name, driver_version, device_version;
  bool is_gpu;
  cl_ulong global_memory_bytes, max_alloc_bytes;
  cl_uint compute_units;
};

// Every device of every platform. Throws NoPlatformError if there is no OpenCL platform.
std::vector<DeviceInfo> list_devices();

// SPEC: an index from list_devices(), or a case-insensitive substring of the device or platform
// name; empty: the first GPU, else the first CPU, else the first device. Throws DeviceError
// listing the devices when nothing matches.
DeviceInfo select_device(const std::string& spec);

struct DeviceContext {
  DeviceInfo info;
  cl::Context context;
  cl::CommandQueue queue;   // in-order, profiling enabled (launch times go to the stats)
  explicit DeviceContext(const DeviceInfo& info);
  std::string description() const;  // "device name (platform, driver x)"
};

}  // namespace bp

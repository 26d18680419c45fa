#include "device/device_context.h"

#include <algorithm>
#include <cctype>

namespace bp {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
  return s;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error&) {
    platforms.clear();  // CL_PLATFORM_NOT_FOUND_KHR from the ICD loader
  }
  if (platforms.empty())
    throw NoPlatformError(
        "no OpenCL platform found: install an OpenCL driver, e.g. `apt-get install pocl-opencl-icd` "
        "for the CPU (or your GPU vendor's ICD)");
  std::vector<DeviceInfo> out;
  for (const cl::Platform& p : platforms) {
    std::vector<cl::Device> devices;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // a platform without devices
    }
    for (const cl::Device& d : devices) {
      DeviceInfo info;
      info.index = int(out.size());
      info.platform = p;
      info.device = d;
      info.platform_name = trimmed(p.getInfo<CL_PLATFORM_NAME>());
      info.device_name = trimmed(d.getInfo<CL_DEVICE_NAME>());
      info.driver_version = trimmed(d.getInfo<CL_DRIVER_VERSION>());
      info.device_version = trimmed(d.getInfo<CL_DEVICE_VERSION>());
      info.is_gpu = (d.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) != 0;
      info.global_memory_bytes = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
      info.max_alloc_bytes = d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
      info.compute_units = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
      out.push_back(info);
    }
  }
  if (out.empty())
    throw NoPlatformError("OpenCL platforms found but no devices: check your OpenCL driver installation "
                          "(`clinfo -l`), or install pocl-opencl-icd");
  return out;
}

DeviceInfo select_device(const std::string& spec) {
  std::vector<DeviceInfo> devices = list_devices();
  if (spec.empty()) {
    for (const DeviceInfo& d : devices)
      if (d.is_gpu) return d;
    for (const DeviceInfo& d : devices)
      if (d.device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) return d;
    return devices.front();
  }
  bool numeric = std::all_of(spec.begin(), spec.end(), [](unsigned char c) { return std::isdigit(c); });
  if (numeric) {
    std::size_t index = std::stoul(spec);
    if (index < devices.size()) return devices[index];
  } else {
    for (const DeviceInfo& d : devices)
      if (lower(d.device_name).find(lower(spec)) != std::string::npos ||
          lower(d.platform_name).find(lower(spec)) != std::string::npos)
        return d;
  }
  std::string msg = "no OpenCL device matches --device '" + spec + "'; available:";
  for (const DeviceInfo& d : devices)
    msg += " [" + std::to_string(d.index) + "] " + d.device_name + " (" + d.platform_name + ");";
  msg.pop_back();
  throw DeviceError(msg);
}

DeviceContext::DeviceContext(const DeviceInfo& device_info) : info(device_info) {
  try {
    context = cl::Context(info.device);
    queue = cl::CommandQueue(context, info.device, CL_QUEUE_PROFILING_ENABLE);
  } catch (const cl::Error& e) {
    throw DeviceError("cannot open OpenCL device '" + info.device_name + "': " + e.what() + " " +
                      cl_error_name(e.err()));
  }
}

std::string DeviceContext::description() const {
  return info.device_name + " (" + info.platform_name + ", driver " + info.driver_version + ")";
}

}  // namespace bp

// Kernel programs: assembled from the embedded sources, built with explicit options, and kept in a
// persistent binary cache keyed on everything that changes the binary.
#pragma once
#include "device/device_context.h"
#include <filesystem>
#include <string>

namespace bp {

struct BuiltProgram {
  cl::Program program;
  double build_seconds = 0.0;  // wall time to get a usable program (cache hit or compile)
  bool from_cache = false;
};

// `render --verbose`: also print the compiler's output and build log of every program built from
// source (they are always in the error when a build fails).
void set_verbose_kernel_builds(bool verbose);

// Where binaries are cached: $BUNDLEPATH_CACHE_DIR, else $XDG_CACHE_HOME/bundlepath/kernels, else
// ~/.cache/bundlepath/kernels. BUNDLEPATH_CACHE_DIR=off disables the cache.
std::filesystem::path kernel_cache_dir();

// Cache key: FNV-1a 64 over (source after includes, options, platform, device, driver version).
std::string kernel_cache_key(const std::string& source, const std::string& options, const DeviceInfo& device);

// Builds kernels/<main_file> with "-cl-std=CL1.2 " + extra_options. What the compiler prints while
// building from source is kept off stderr; on a compile error it throws DeviceError carrying that
// and the device's build log (file names and lines are the real ones).
BuiltProgram build_program(const DeviceContext& device, const std::string& main_file,
                           const std::string& extra_options = "");

}  // namespace bp

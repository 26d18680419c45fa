// The one include of opencl.hpp (exceptions on, OpenCL 1.2 API), plus the error vocabulary.
#pragma once
#include <CL/opencl.hpp>
#include <stdexcept>
#include <string>

namespace bp {

// Symbolic name of an OpenCL error code, e.g. "CL_OUT_OF_RESOURCES".
const char* cl_error_name(cl_int code);

// Any OpenCL failure, rephrased for a person: what was being done, and the error's name.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// No OpenCL platform at all (no ICD installed): the CLI exits with code 2 and names the package.
class NoPlatformError : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

}  // namespace bp

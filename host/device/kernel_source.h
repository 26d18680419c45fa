// Assembles a kernel's full source from the embedded files: every #include "..." is inlined once,
// with #line directives so a device build log names the real file and line.
#pragma once
#include <string>

namespace bp {

// Throws std::runtime_error if the file or one of its includes is not embedded.
std::string assemble_kernel_source(const std::string& main_file);

}  // namespace bp

// The subcommands; each returns the process exit code.
#pragma once
#include "cli/options.h"
#include <string>
#include <vector>

namespace bp {

int run_devices();
int run_render(const RenderOptions& options);
// bundlepath compare IMAGE.exr REFERENCE.exr [--layer NAME] [--json]
int run_compare(const std::vector<std::string>& args);

}  // namespace bp

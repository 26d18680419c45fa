// The subcommands; each returns the process exit code.
#pragma once
#include "cli/options.h"

namespace bp {

int run_devices();
int run_render(const RenderOptions& options);

}  // namespace bp

// The subcommands; each returns the process exit code.
#pragma once
#include "cli/options.h"
#include "render/ranks.h"
#include <string>
#include <vector>

namespace bp {

int run_devices();
// bundlepath --version: the version and the optional parts found (OpenImageDenoise, MPI, ffmpeg).
int run_version();
// ranks: the MPI job's processes (render/ranks.h); one when mpirun did not start this one.
int run_render(const RenderOptions& options, const Ranks& ranks);
// bundlepath compare IMAGE.exr REFERENCE.exr [--layer NAME] [--json]
int run_compare(const std::vector<std::string>& args);

}  // namespace bp

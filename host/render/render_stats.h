// The stats file (--stats): what the render did, how long each part took, and its error estimate.
#pragma once
#include "render/render_job.h"

namespace bp {

struct RenderState;

// Throws std::runtime_error naming the file if it cannot be written.
void write_stats(const RenderState& s, const RenderResult& result);

}  // namespace bp

// The stats file (--stats): what the render did, how long each part took, and its error estimate.
#pragma once
#include "render/render_job.h"

namespace bp {

struct RenderState;

// The stats of a finished render (its result holds the counts and the reference metrics).
nlohmann::json render_stats(const RenderState& s, const RenderResult& result);

}  // namespace bp

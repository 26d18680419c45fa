// Command-line options of `bundlepath render`, parsed and range-checked.
#pragma once
#include "render/render_spec.h"
#include <string>
#include <vector>

namespace bp {

// The options of one render are a RenderSpec (render/render_spec.h): the engine's input.
using RenderOptions = RenderSpec;

// Parses the arguments after "render". Throws UsageError.
RenderOptions parse_render_options(const std::vector<std::string>& args);

const char* render_help();      // the everyday options
const char* render_help_all();  // and the estimator's tuning knobs
const char* main_help();

}  // namespace bp

// A render's outputs: its layers (DESIGN.md §7), the EXR/PNG files and contact sheet, and the
// layers' errors against --reference.
#pragma once
#include "image/image.h"
#include "render/render_job.h"

#include <string>
#include <utility>
#include <vector>

namespace bp {

struct RenderState;

// "" is the combined image (R,G,B = pt + rb of the weighted images, eq. 3); then pt, rb (combined
// renders) and pt_raw, rb_raw (--layers all).
struct RenderLayers {
  std::vector<std::pair<std::string, ImageRGB>> images;
  const ImageRGB* find(const std::string& name) const;
};
RenderLayers make_layers(const RenderState& s);

// Writes PREFIX.exr (the layers and the standard error), PREFIX.png and the contact sheet; sets the
// result's paths.
void write_images(const RenderState& s, const RenderLayers& layers, RenderResult& result);

// Each layer against the reference ("combined" for the combined image); empty without one.
std::vector<std::pair<std::string, ErrorMetrics>> compare_layers(const RenderState& s, const RenderLayers& layers);

}  // namespace bp

// A render's outputs: its layers (docs/design.md §7), the EXR/PNG files and contact sheet, and the
// layers' errors against --reference.
#pragma once
#include "image/image.h"
#include "image/share_correction.h"
#include "render/render_job.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bp {

class Denoiser;
struct RenderState;
struct RenderView;

// "" is the combined image (R,G,B = pt + rb of the weighted images, eq. 3; denoised with --denoise,
// then "raw" is the render's own); then pt, rb (combined renders) and pt_raw, rb_raw (--layers all).
struct RenderLayers {
  std::vector<std::pair<std::string, ImageRGB>> images;
  const ImageRGB* find(const std::string& name) const;
};
RenderLayers make_layers(const RenderState& s, const RenderView& view);
// The factors on the view's RB layer in the combined image, per pixel and channel (--rb-level,
// image/rb_level.h): under the regional level with RB's weights from the view's regional error, so
// that the image is the estimator whose error that reports.
std::vector<double> rb_pixel_factors(const RenderView& view);
// RB's weight per region that those factors take from the regional error (empty: RbLevel's own).
std::vector<double> rb_region_weights(const RenderView& view);

// --denoise: the combined image ("") denoised by OpenImageDenoise with the view's prefiltered albedo
// and normal, the render's own kept as "raw" after it.
void denoise_image(const Denoiser& denoiser, const RenderView& view, RenderLayers& layers);

// --rb-level consistent (image/share_correction.h): RB's share as the image has it (its layer times
// the regional field) corrected by PT's estimate of it; nullopt under the other levels.
std::optional<ShareCorrection> consistent_share(const RenderState& s, const RenderView& view);

// Writes the view's PREFIX.exr (the layers and the standard error), PREFIX.png and the contact sheet
// (one view); gives their paths.
RenderFrame write_images(const RenderState& s, const RenderView& view, const RenderLayers& layers);

// --video: the frames' PNGs encoded by ffmpeg at --fps (H.264, yuv420p); throws std::runtime_error
// when ffmpeg fails. Sets the result's video_path.
void encode_video(const RenderState& s, RenderResult& result);

// Each layer against the reference ("combined" for the combined image); empty without one.
std::vector<std::pair<std::string, ErrorMetrics>> compare_layers(const RenderState& s, const RenderLayers& layers);

}  // namespace bp

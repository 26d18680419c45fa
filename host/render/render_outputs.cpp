#include "render/render_outputs.h"

#include "image/contact_sheet.h"
#include "image/denoiser.h"
#include "image/video.h"
#include "render/render_state.h"

#include <array>
#include <cmath>
#include <filesystem>

namespace bp {
namespace {
// a + b, each value of b times its factor (none: 1).
ImageRGB sum_images(const ImageRGB& a, const ImageRGB& b, const std::vector<double>& b_factors) {
  ImageRGB out = a;
  for (std::size_t i = 0; i < out.rgb.size(); ++i)
    out.rgb[i] += float(double(b.rgb[i]) * (b_factors.empty() ? 1.0 : b_factors[i]));
  return out;
}

// Each pixel's region's relative standard error (image/regional_error.h), in every channel; 0 where
// it is not known (a black region, or fewer than two batches).
ImageRGB region_error_image(const RegionalError& e) {
  const RegionGrid& g = e.grid();
  std::vector<double> relative = e.relative_standard_errors();
  for (double& v : relative)
    if (!std::isfinite(v)) v = 0.0;
  ImageRGB out(g.width, g.height);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      for (std::size_t c = 0; c < 3; ++c)
        out.rgb[(std::size_t(y) * std::size_t(g.width) + std::size_t(x)) * 3 + c] = float(relative[g.region_of(x, y)]);
  return out;
}
}  // namespace

const ImageRGB* RenderLayers::find(const std::string& name) const {
  for (const auto& [n, img] : images)
    if (n == name) return &img;
  return nullptr;
}

std::vector<double> rb_region_weights(const RenderView& view) {
  const RegionGrid& grid = view.rb_level->grid();
  const bool regional = grid.count() > 1 && view.regional_error && view.regional_error->grid().columns == grid.columns &&
                        view.regional_error->grid().rows == grid.rows;
  return regional ? view.regional_error->rb_weights() : std::vector<double>{};
}

std::vector<double> rb_pixel_factors(const RenderView& view) { return view.rb_level->pixel_factors(rb_region_weights(view)); }

std::optional<ShareCorrection> consistent_share(const RenderState& s, const RenderView& view) {
  if (!view.pt_share_batches || !view.rb_level) return std::nullopt;
  const ImageRGB rb = sum_images(ImageRGB(s.scene.width, s.scene.height), view.rb_accum.mean(), rb_pixel_factors(view));
  ImageRGB d = view.pt_accum.raw_mean();
  const ImageRGB w = view.pt_accum.mean();
  for (std::size_t i = 0; i < d.rgb.size(); ++i) d.rgb[i] -= w.rgb[i];
  return correct_share(rb, d, view.pt_share_batches->variance_of_mean());
}

RenderLayers make_layers(const RenderState& s, const RenderView& view) {
  const int width = s.scene.width, height = s.scene.height;
  const bool pt = !s.pt.empty();
  RenderLayers layers;
  ImageRGB pt_image = pt ? view.pt_accum.mean() : ImageRGB(width, height);
  ImageRGB rb_image = s.rb ? view.rb_accum.mean() : ImageRGB(width, height);
  // The combined image, pt + s·rb with --rb-level's field s (image/rb_level.h); the rb layer stays
  // RB's own weighted estimate.
  // Under --rb-level consistent, that share corrected by PT's estimate of it (image/share_correction.h).
  if (std::optional<ShareCorrection> share = consistent_share(s, view)) {
    layers.images.emplace_back("", sum_images(pt_image, share->share, {}));
  } else {
    const std::vector<double> rb_factors = view.rb_level ? rb_pixel_factors(view) : std::vector<double>{};
    layers.images.emplace_back("", sum_images(pt_image, rb_image, rb_factors));
  }
  // No rb layers where --ratio auto chose the path tracer alone: RB rendered nothing.
  if (s.shape) {
    layers.images.emplace_back("pt", pt_image);
    if (s.rb_renders()) layers.images.emplace_back("rb", rb_image);
  }
  if (s.spec.all_layers) {
    if (pt) layers.images.emplace_back("pt_raw", view.pt_accum.raw_mean());
    if (s.rb_renders()) layers.images.emplace_back("rb_raw", view.rb_accum.raw_mean());
  }
  return layers;
}

void denoise_image(const Denoiser& denoiser, const RenderView& view, RenderLayers& layers) {
  ImageRGB& beauty = layers.images.front().second;
  ImageRGB denoised = denoiser.denoise(beauty, view.prefiltered.albedo, view.prefiltered.normal);
  layers.images.insert(layers.images.begin() + 1, {"raw", std::move(beauty)});
  layers.images.front().second = std::move(denoised);
}

RenderFrame write_images(const RenderState& s, const RenderView& view, const RenderLayers& layers) {
  const RenderSpec& o = s.spec;
  std::filesystem::path prefix(view.out_prefix);
  if (prefix.has_parent_path()) std::filesystem::create_directories(prefix.parent_path());
  RenderFrame result;
  result.exr_path = view.out_prefix + ".exr";
  result.png_path = view.out_prefix + ".png";
  std::vector<ImageLayer> exr_layers;
  for (const auto& [name, img] : layers.images) exr_layers.push_back({name, &img});
  // Each pixel's standard error of the combined image (docs/design.md §9), beside the layers.
  const ImageRGB standard_error = view.error_estimate->standard_error();
  exr_layers.push_back({"stderr", &standard_error});
  // Each region's relative standard error of its mean luminance (docs/design.md §9, "Regional error").
  const ImageRGB region_error = region_error_image(*view.regional_error);
  exr_layers.push_back({"region_error", &region_error});
  // What a denoiser reads (docs/design.md §13), for OpenImageDenoise here or a compositor elsewhere.
  exr_layers.push_back({"albedo", &view.features.albedo});
  exr_layers.push_back({"normal", &view.features.normal});
  write_exr(result.exr_path, exr_layers);
  write_png(result.png_path, layers.images.front().second, o.exposure);
  if (!o.contact_sheet_path.empty()) {
    const ImageRGB* reference = s.scene.reference ? &*s.scene.reference : nullptr;
    write_contact_sheet(o.contact_sheet_path,
                        {{"non-weighted PT", layers.find("pt_raw")},
                         {"weighted PT", s.shape ? layers.find("pt") : nullptr},
                         {"combined", &layers.images.front().second},
                         {"non-weighted RB", layers.find("rb_raw")},
                         {"weighted RB", s.shape ? layers.find("rb") : nullptr},
                         {"reference", reference}},
                        o.exposure);
  }
  return result;
}

void encode_video(const RenderState& s, RenderResult& result) {
  const RenderSpec& o = s.spec;
  std::filesystem::path video(o.video_path);
  if (video.has_parent_path()) std::filesystem::create_directories(video.parent_path());
  encode_png_sequence(o.out_prefix + "_%04d.png", o.views.fps, o.video_path);
  result.video_path = o.video_path;
}

std::vector<std::pair<std::string, ErrorMetrics>> compare_layers(const RenderState& s, const RenderLayers& layers) {
  std::vector<std::pair<std::string, ErrorMetrics>> out;
  if (!s.scene.reference) return out;
  for (const auto& [name, img] : layers.images)
    out.emplace_back(name.empty() ? "combined" : name, compare_images(img, *s.scene.reference));
  return out;
}

}  // namespace bp

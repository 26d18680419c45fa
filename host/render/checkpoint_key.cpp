#include "render/checkpoint_key.h"

#include <cstdio>
#include <filesystem>

namespace bp {

std::string options_key(const RenderSpec& o, int width, int height, float patch_size, std::uint32_t bins,
                        const std::optional<RoundShape>& shape, const std::string& eye_direct) {
  std::string key = "scene=" + std::filesystem::absolute(o.scene).lexically_normal().string() +
                    ";mode=" + o.mode + ";size=" + std::to_string(width) + "x" + std::to_string(height) +
                    ";seed=" + std::to_string(o.seed) + ";patch_size=" + std::to_string(patch_size) +
                    ";patch_clusters=" + (o.patch_clusters ? "on" : "off") +
                    ";patch_refine=" + (o.patch_refine ? "on" : "off") +
                    (o.patch_budget > 0 ? ";patches=" + std::to_string(o.patch_budget) : "") +
                    ";max_depth=" + std::to_string(o.max_depth) + ";layers=" + (o.all_layers ? "all" : "default") +
                    ";light_sampling=" + (light_sampling_applies(o) ? "on;light_selection=" + o.light_selection : "off") +
                    ";kernels=" + (o.generic_kernels ? "generic" : "specialised");
  if (o.environment != std::array<float, 3>{0.0f, 0.0f, 0.0f})
    key += ";environment=" + std::to_string(o.environment[0]) + "," + std::to_string(o.environment[1]) + "," +
           std::to_string(o.environment[2]);
  if (!o.environment_path.empty())
    key += ";environment=" + std::filesystem::absolute(o.environment_path).lexically_normal().string();
  if (!o.views.camera.empty()) key += ";camera=" + o.views.camera;  // --camera: other than the default view
  if (o.mode != "pt")
    key += ";bins=" + std::to_string(bins) + ";warmup=" + std::to_string(o.warmup) +
           (o.contact_depth >= 0.0f ? ";contact_depth=" + std::to_string(o.contact_depth) : "") +
           ";shading=" + (o.gouraud ? "gouraud" : "flat") + (o.eye_blocks ? "" : ";eye_gather=every") +
           ";directions=" + o.rb_directions;
  if (shape)
    key += ";weights=" + o.weights + ";beta=" + o.beta + ";light_rate=" + std::to_string(o.light_rate) +
           (o.rb_sun_own ? ";rb_sun=own" : "") +
           ";eye_direct=" + eye_direct + (rb_level_corrected(o) ? ";rb_level=" + o.rb_level : "") +
           ";regions=" + std::to_string(o.regions) +
           ";round=" + std::to_string(shape->pt_samples) + "spp+" + std::to_string(shape->rb_iterations) + "it";
  return key;
}

std::string views_key(const RenderSpec& o, const std::vector<SceneCamera>& views) {
  if (!o.views.frames()) return "";
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the cameras' floats
  for (const SceneCamera& c : views) {
    const float values[] = {c.position.x, c.position.y, c.position.z, c.forward.x, c.forward.y,
                            c.forward.z,  c.up.x,       c.up.y,       c.up.z,      c.yfov};
    const auto* bytes = reinterpret_cast<const unsigned char*>(values);
    for (std::size_t i = 0; i < sizeof values; ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
  }
  char text[64];
  std::snprintf(text, sizeof text, ";views=%zu:%016llx", views.size(), static_cast<unsigned long long>(hash));
  return text;
}

std::optional<RoundShape> round_of_key(const std::string& key) {
  const std::string tag = ";round=";
  const std::size_t at = key.find(tag);
  if (at == std::string::npos) return std::nullopt;
  unsigned long long spp = 0, iterations = 0;
  // 0 iterations: the path tracer alone (--ratio auto's choice, passes/combined.h); 0 spp: RB alone.
  if (std::sscanf(key.c_str() + at + tag.size(), "%lluspp+%lluit", &spp, &iterations) != 2 || spp + iterations == 0)
    return std::nullopt;
  return RoundShape{std::uint32_t(spp), std::uint32_t(iterations)};
}

std::optional<bool> eye_direct_shared_of_key(const std::string& key) {
  if (key.find(";eye_direct=shared") != std::string::npos) return true;
  if (key.find(";eye_direct=pt") != std::string::npos) return false;
  return std::nullopt;
}

}  // namespace bp

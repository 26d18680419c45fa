// Textures on the host (docs/design.md §6): decoding images into the scene's texel buffer, the glTF
// sampler and KHR_texture_transform as a TextureView, per-triangle texcoords for the device, and
// the per-patch means RB reflects with. Sampling itself is kernels/shared/texture.h.
#pragma once
#include "scene/patches.h"
#include "scene/scene.h"
#include "kernels/shared/texture.h"
#include "kernels/shared/types.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bp {

// Limits on decoded images (README, "glTF mapping"): a side of at most kMaxTextureSide texels, and
// at most kMaxSceneTexels texels in a scene (4 bytes each on the device: 1 GiB).
inline constexpr int kMaxTextureSide = 16384;
inline constexpr std::uint64_t kMaxSceneTexels = std::uint64_t(1) << 28;

struct DecodedImage {
  int width = 0, height = 0;
  std::vector<std::uint32_t> rgba;  // RGBA8 packed little-end first (R in the low byte), rows top to bottom
};

// Decodes PNG or JPEG bytes (stb_image) to RGBA8. nullopt and *error set on failure: undecodable,
// or a side beyond kMaxTextureSide (checked from the header before decoding).
std::optional<DecodedImage> decode_image(const unsigned char* bytes, std::size_t size, std::string* error);

// glTF sampler wrap mode (10497 REPEAT, 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT) as BP_WRAP_*;
// nullopt for anything else.
std::optional<std::uint32_t> wrap_mode_from_gltf(int mode);

// KHR_texture_transform's uv' = T R S uv as TextureView::transform (column-major 2x3).
void texture_transform(float offset_u, float offset_v, float rotation, float scale_u, float scale_v,
                       float out[6]);

// Per triangle, scene.uv_slots texcoord sets of 3 corners (u, v): the layout TextureSet reads;
// empty without textures.
std::vector<float> pack_texcoords(const Scene& scene);

// A TextureSet over host arrays (host tests, the patch means). `texcoords` from pack_texcoords and
// `material_textures` from pack_material_textures must outlive it.
std::vector<MaterialTextures> pack_material_textures(const Scene& scene);
TextureSet host_texture_set(const Scene& scene, const std::vector<MaterialTextures>& material_textures,
                            const std::vector<float>& texcoords);

// Samples per patch for its mean texel: kPatchMeanSamplesPerSide^2 stratified points.
inline constexpr int kPatchMeanSamplesPerSide = 16;

// Per patch, its material with the textured values replaced by their means over the patch's area
// (base colour, metallic, roughness, emission, specular and its f0; kd of a Lambert one): what RB
// reflects and emits with, and what every weight input (s, the lobe choice, p_uv) reads on both
// sides. `materials` is pack_materials' list.
std::vector<Material> patch_mean_materials(const Scene& scene, const PatchLayout& patches,
                                           const std::vector<Material>& materials);

// alphaMode MASK: per element (sub-triangle, in patch order), the fraction of its area that is
// surface (the same 256 centroids), over which RB's gather spreads the power its fragments receive.
std::vector<float> element_alpha_coverage(const Scene& scene, const PatchLayout& patches);

}  // namespace bp

// The texture sampling shared with the kernels (kernels/shared/texture.h), on the host: sRGB decode,
// the three glTF wrap modes, bilinear and nearest filtering, KHR_texture_transform, and the
// metallic-roughness mapping texel by texel.
#include "kernels/shared/texture.h"
#include "scene/textures.h"

#include <gtest/gtest.h>
#include <cmath>
#include <vector>

namespace bp {
namespace {

std::uint32_t rgba(int r, int g, int b, int a) { return std::uint32_t(r) | g << 8 | b << 16 | std::uint32_t(a) << 24; }

TextureView view_of(std::uint32_t width, std::uint32_t height, std::uint32_t wrap_s, std::uint32_t wrap_t,
                    std::uint32_t extra = 0) {
  TextureView v{};
  v.width = width;
  v.height = height;
  v.flags = wrap_s | wrap_t << BP_TEXTURE_WRAP_T_SHIFT | extra;
  texture_transform(0, 0, 0, 1, 1, v.transform);
  return v;
}

TEST(Texture, SrgbDecodeFollowsIec61966) {
  EXPECT_FLOAT_EQ(srgb_to_linear(0.0f), 0.0f);
  EXPECT_NEAR(srgb_to_linear(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(srgb_to_linear(0.04045f), 0.04045f / 12.92f, 1e-7f);  // the linear segment's end
  EXPECT_NEAR(srgb_to_linear(0.5f), std::pow((0.5 + 0.055) / 1.055, 2.4), 1e-6);
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.214041f, 1e-5f);
  // a texel is decoded per channel when the view is sRGB, alpha never
  const std::vector<std::uint32_t> texels = {rgba(128, 0, 255, 128)};
  const TextureView srgb = view_of(1, 1, BP_WRAP_REPEAT, BP_WRAP_REPEAT, BP_TEXTURE_SRGB);
  const Texel t = texture_fetch(texels.data(), &srgb, 0, 0);
  EXPECT_NEAR(t.r, srgb_to_linear(128.0f / 255.0f), 1e-6f);
  EXPECT_FLOAT_EQ(t.g, 0.0f);
  EXPECT_NEAR(t.b, 1.0f, 1e-6f);
  EXPECT_NEAR(t.a, 128.0f / 255.0f, 1e-6f);
  const TextureView linear = view_of(1, 1, BP_WRAP_REPEAT, BP_WRAP_REPEAT);
  EXPECT_NEAR(texture_fetch(texels.data(), &linear, 0, 0).r, 128.0f / 255.0f, 1e-6f);
}

TEST(Texture, WrapModesFollowGltf) {
  // REPEAT: period n
  EXPECT_EQ(texture_wrap(-1, 4, BP_WRAP_REPEAT), 3);
  EXPECT_EQ(texture_wrap(4, 4, BP_WRAP_REPEAT), 0);
  EXPECT_EQ(texture_wrap(-5, 4, BP_WRAP_REPEAT), 3);
  EXPECT_EQ(texture_wrap(9, 4, BP_WRAP_REPEAT), 1);
  // CLAMP_TO_EDGE: the edge texels
  EXPECT_EQ(texture_wrap(-1, 4, BP_WRAP_CLAMP_TO_EDGE), 0);
  EXPECT_EQ(texture_wrap(7, 4, BP_WRAP_CLAMP_TO_EDGE), 3);
  EXPECT_EQ(texture_wrap(2, 4, BP_WRAP_CLAMP_TO_EDGE), 2);
  // MIRRORED_REPEAT: 0 1 2 3 3 2 1 0 0 1 ...
  const int expected[] = {0, 1, 2, 3, 3, 2, 1, 0, 0, 1};
  for (int i = 0; i < 10; ++i) EXPECT_EQ(texture_wrap(i, 4, BP_WRAP_MIRRORED_REPEAT), expected[i]) << i;
  EXPECT_EQ(texture_wrap(-1, 4, BP_WRAP_MIRRORED_REPEAT), 0);
  EXPECT_EQ(texture_wrap(-2, 4, BP_WRAP_MIRRORED_REPEAT), 1);
  EXPECT_EQ(texture_wrap(-5, 4, BP_WRAP_MIRRORED_REPEAT), 3);
  for (std::uint32_t mode : {BP_WRAP_REPEAT, BP_WRAP_CLAMP_TO_EDGE, BP_WRAP_MIRRORED_REPEAT})
    for (int i = -40; i < 40; ++i) {
      const int w = texture_wrap(i, 3, mode);
      EXPECT_TRUE(w >= 0 && w < 3) << "mode " << mode << " i " << i;
    }
}

TEST(Texture, BilinearBetweenTexelCentresNearestWithinTexels) {
  // two texels in a row: red 0 and red 255 (linear), texel centres at u = 1/4 and 3/4
  const std::vector<std::uint32_t> texels = {rgba(0, 0, 0, 255), rgba(255, 0, 0, 255)};
  const TextureView clamp = view_of(2, 1, BP_WRAP_CLAMP_TO_EDGE, BP_WRAP_CLAMP_TO_EDGE);
  EXPECT_NEAR(texture_sample(texels.data(), &clamp, 0.25f, 0.5f).r, 0.0f, 1e-6f);
  EXPECT_NEAR(texture_sample(texels.data(), &clamp, 0.75f, 0.5f).r, 1.0f, 1e-6f);
  EXPECT_NEAR(texture_sample(texels.data(), &clamp, 0.5f, 0.5f).r, 0.5f, 1e-6f);
  EXPECT_NEAR(texture_sample(texels.data(), &clamp, 0.375f, 0.9f).r, 0.25f, 1e-6f);
  EXPECT_NEAR(texture_sample(texels.data(), &clamp, 0.1f, 0.5f).r, 0.0f, 1e-6f);   // clamped to the edge texel
  EXPECT_NEAR(texture_sample(texels.data(), &clamp, 0.95f, 0.5f).r, 1.0f, 1e-6f);
  // REPEAT: at u = 0 halfway between the last texel and the first
  const TextureView repeat = view_of(2, 1, BP_WRAP_REPEAT, BP_WRAP_REPEAT);
  EXPECT_NEAR(texture_sample(texels.data(), &repeat, 0.0f, 0.5f).r, 0.5f, 1e-6f);
  EXPECT_NEAR(texture_sample(texels.data(), &repeat, 1.125f, 0.5f).r, 0.25f, 1e-6f);
  EXPECT_NEAR(texture_sample(texels.data(), &repeat, -0.875f, 0.5f).r, 0.25f, 1e-6f);
  // MIRRORED_REPEAT: at u = 1 the mirror's first texel is the last one again
  const TextureView mirror = view_of(2, 1, BP_WRAP_MIRRORED_REPEAT, BP_WRAP_MIRRORED_REPEAT);
  EXPECT_NEAR(texture_sample(texels.data(), &mirror, 1.0f, 0.5f).r, 1.0f, 1e-6f);
  EXPECT_NEAR(texture_sample(texels.data(), &mirror, 1.5f, 0.5f).r, 0.5f, 1e-6f);
  // NEAREST: the texel containing u
  const TextureView nearest = view_of(2, 1, BP_WRAP_CLAMP_TO_EDGE, BP_WRAP_CLAMP_TO_EDGE, BP_TEXTURE_NEAREST);
  EXPECT_EQ(texture_sample(texels.data(), &nearest, 0.49f, 0.5f).r, 0.0f);
  EXPECT_EQ(texture_sample(texels.data(), &nearest, 0.51f, 0.5f).r, 1.0f);
  // in t alike, rows top to bottom: a 1 x 2 image, row 0 at t in [0, 1/2)
  const TextureView column = view_of(1, 2, BP_WRAP_CLAMP_TO_EDGE, BP_WRAP_CLAMP_TO_EDGE, BP_TEXTURE_NEAREST);
  EXPECT_EQ(texture_sample(texels.data(), &column, 0.5f, 0.2f).r, 0.0f);
  EXPECT_EQ(texture_sample(texels.data(), &column, 0.5f, 0.8f).r, 1.0f);
}

// KHR_texture_transform: uv' = T R S uv with the spec's R (column-major mat3(cos, sin, 0, -sin, cos, 0, ...)).
TEST(Texture, TextureTransformIsTranslationRotationScale) {
  float m[6];
  texture_transform(0.5f, 0.25f, 0.0f, 2.0f, 3.0f, m);
  EXPECT_FLOAT_EQ(m[0] * 1 + m[2] * 1 + m[4], 2.5f);
  EXPECT_FLOAT_EQ(m[1] * 1 + m[3] * 1 + m[5], 3.25f);
  const float r = 0.392699f;  // the TextureTransformTest sample's rotation
  texture_transform(0.0f, 0.0f, r, 1.0f, 1.0f, m);
  // (1, 0) -> (cos r, sin r), (0, 1) -> (-sin r, cos r)
  EXPECT_NEAR(m[0], std::cos(r), 1e-6f);
  EXPECT_NEAR(m[1], std::sin(r), 1e-6f);
  EXPECT_NEAR(m[2], -std::sin(r), 1e-6f);
  EXPECT_NEAR(m[3], std::cos(r), 1e-6f);
}

// A 1 x 1 metallic-roughness texel (G roughness, B metallic) times the factors gives the point's
// metallic and roughness, the base colour texel times its factor the base colour and alpha.
TEST(Texture, TexelMaterialReadsMetallicRoughnessTexels) {
  const std::vector<std::uint32_t> texels = {rgba(200, 128, 64, 51), rgba(0, 204, 255, 255)};
  std::vector<TextureView> views = {view_of(1, 1, BP_WRAP_REPEAT, BP_WRAP_REPEAT),
                                    view_of(1, 1, BP_WRAP_REPEAT, BP_WRAP_REPEAT)};
  views[1].first_texel = 1;
  MaterialTextures mt = SceneMaterial::untextured();
  mt.base_color = 0;
  mt.metallic_roughness = 1;
  mt.metallic_factor = 0.5f;
  mt.roughness_factor = 0.5f;
  mt.base_color_factor[1] = 0.5f;
  mt.base_color_factor[3] = 0.5f;
  const std::vector<MaterialTextures> materials = {mt};
  const std::vector<float> texcoords(6, 0.5f);
  const TextureSet set{views.data(), texels.data(), materials.data(), texcoords.data(), 1};
  const TexelMaterial t = texel_material(&set, &mt, 0, 0.3f, 0.3f);
  EXPECT_NEAR(t.metallic, 0.5f * 1.0f, 1e-6f);   // B 255
  EXPECT_NEAR(t.roughness, 0.5f * 0.8f, 1e-6f);  // G 204
  const float base[3] = {200.0f / 255.0f, 0.5f * 128.0f / 255.0f, 64.0f / 255.0f};  // linear view, factor (1, 0.5, 1)
  const float got[3] = {t.base_color.x, t.base_color.y, t.base_color.z};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], base[c], 1e-6f) << c;
  EXPECT_NEAR(t.alpha, 0.5f * 0.2f, 1e-6f);
}

}  // namespace
}  // namespace bp

// A textured quad seen head-on reproduces its texture (issue #13): tests/data/gltf/good/textured-quad.gltf,
// a Lambert quad whose 4 x 4 sRGB baseColorTexture (NEAREST, so each texel covers whole pixels)
// fills the 90-degree view, under a uniform environment of radiance L: every point of it reads
// kd(texel) L, as a convex surface under a uniform environment does -- in the path tracer, in ray
// bundles alone (whose eye gather reads the texel, its patches the patch mean), and combined.
#include "kernel/device_fixture.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"
#include "scene/lights.h"
#include "scene/textures.h"
#include "kernels/shared/bvh.h"
#include "kernels/shared/camera.h"

#include <gtest/gtest.h>
#include <cmath>
#include <vector>

namespace bp::test {
namespace {

const glm::vec3 kEnvironment(1.0f, 0.5f, 0.25f);
constexpr int kSize = 16, kTexels = 4, kBlock = kSize / kTexels;  // 4 x 4 pixels per texel

Scene textured_quad(const char* file = "good/textured-quad.gltf") {
  Scene scene = load_gltf(test_file(file));
  scene.environment = kEnvironment;
  return scene;
}

// The albedo of texel (x, y), channel c: the sRGB texel decoded (metallic 0, specular 0: kd = base colour).
double texel_albedo(const Scene& scene, int x, int y, int c) {
  const std::uint32_t t = scene.texels[scene.texture_views[0].first_texel + kTexels * y + x];
  return srgb_to_linear(float((t >> (8 * c)) & 255u) / 255.0f);
}

// Mean of channel c over the pixels of texel (x, y).
double block_mean(const ImageRGB& image, int x, int y, int c) {
  double sum = 0.0;
  for (int py = y * kBlock; py < (y + 1) * kBlock; ++py)
    for (int px = x * kBlock; px < (x + 1) * kBlock; ++px) sum += image.pixel(px, py)[c];
  return sum / (kBlock * kBlock);
}

// The smallest continuation probability s of any patch in render_pt's layout: s = max(kd + ks) of
// the patch's mean material, which the path tracer's Russian roulette uses.
double min_continuation(const Scene& scene) {
  const PatchLayout patches = build_patch_layout(scene, default_patch_size(scene));
  double s = 1.0;
  const LightList lights = build_light_list(scene, build_bvh(scene.triangles));
  for (const Material& m : patch_mean_materials(scene, patches, pack_materials(scene, lights)))
    s = std::min(s, double(std::max({m.kd[0] + m.ks[0], m.kd[1] + m.ks[1], m.kd[2] + m.ks[2]})));
  return s;
}

// The path tracer: a sample is kd L / s with probability s (Russian roulette on the patch's mean
// continuation s; the cosine-sampled bounce leaves the scene with f cos / (s p) = kd / s), else 0, so
// a texel's block of kBlock^2 pixels at spp each is within 5 standard errors
// kd L sqrt((1 - s) / (s spp kBlock^2)) of kd L, s at least min_continuation.
TEST(Textures, TexturedQuadReproducesItsTextureInThePathTracer) {
  const Scene scene = textured_quad();
  const int spp = 64;
  const ImageRGB image = render_pt(scene, kSize, kSize, spp, 3).image;
  const double s_min = min_continuation(scene);
  ASSERT_GT(s_min, 0.1);
  for (int y = 0; y < kTexels; ++y)
    for (int x = 0; x < kTexels; ++x)
      for (int c = 0; c < 3; ++c) {
        const double expected = texel_albedo(scene, x, y, c) * kEnvironment[c];
        const double se = expected * std::sqrt((1.0 - s_min) / (s_min * spp * kBlock * kBlock));
        EXPECT_NEAR(block_mean(image, x, y, c), expected, 5.0 * se + 1e-6) << "texel " << x << "," << y << " channel " << c;
      }
}

// Ray bundles alone and the combination: each texel's block, averaged over independent runs,
// against kd L with its own standard error over the runs (8 of them: 8 standard errors keep the 48
// block-channel comparisons' false alarms below 1 %), each standard error asserted below 2 % of the
// value, so a block that read the patch's mean instead of its texel (the texels differ by 25 % and
// more from their neighbours) fails.
// Khronos' TextureCoordinateTest.gltf (four textured double-sided quads in front of a grey plane,
// seen from the side it is made for) under the environment renders its texture: the path tracer's
// pixels that lie wholly on a quad (whose side towards the camera sees the whole environment: kd(x) L) against the texture's mean over the
// pixel (host ray casts on a 16 x 16 grid, the texel evaluated by the shared code) -- their mean
// within 5 pooled standard errors of the Russian-roulette noise and 1 % for the grid's quadrature,
// and the two images correlated pixel by pixel (a texture ignored or misplaced would not be).
TEST(Textures, TextureCoordinateTestSampleRendersItsTexture) {
  Scene scene = load_gltf(gltf_sample("TextureCoordinateTest.gltf"));
  scene.environment = kEnvironment;
  // the sample is made to be seen from -z (its quads face -z, the grey plane behind them at z = 0.05)
  scene.camera.position = glm::vec3(0.0f, 0.0f, -4.5f);
  scene.camera.forward = glm::vec3(0.0f, 0.0f, 1.0f);
  scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.yfov = 0.6f;  // tan(0.3) 4.5 m = 1.39 m: the quads (to 1.2 m) in view
  for (SceneMaterial& m : scene.materials) {  // its quads are rough metals (metallicFactor 1): made Lambert, kd = base
    m.textures.metallic_factor = 0.0f;
    m.metallic = 0.0f;
    m.ggx = false;
    m.kd = m.base_color;
    m.ks = glm::vec3(0.0f);
  }
  constexpr int size = 32, grid = 16, spp = 64;
  const ImageRGB image = render_pt(scene, size, size, spp, 9).image;
  const FlatBvh bvh = build_bvh(scene.triangles);
  const PatchLayout patches = build_patch_layout(scene, default_patch_size(scene));
  const std::vector<TriangleShading> shading = pack_triangle_shading(scene, patches);
  const std::vector<MaterialTextures> materials = pack_material_textures(scene);
  const std::vector<float> texcoords = pack_texcoords(scene);
  const TextureSet set = host_texture_set(scene, materials, texcoords);
  const CameraParams camera = pack_camera(scene.camera, size, size);
  const float3 o = make_float3(camera.position[0], camera.position[1], camera.position[2]);
  std::vector<double> rendered, expected;
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      double sum = 0.0;
      bool on_quad = true;
      for (int j = 0; j < grid && on_quad; ++j)
        for (int i = 0; i < grid && on_quad; ++i) {
          const float3 d = camera_ray_direction(&camera, std::uint32_t(px), std::uint32_t(py), (i + 0.5f) / grid,
                                                (j + 0.5f) / grid);
          Hit hit;
          on_quad = bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), o, d, BP_FLOAT_MAX, &hit) &&
                    scene.materials[shading[hit.triangle].material].textured();  // double-sided
          if (!on_quad) break;
          const MaterialTextures mt = materials[shading[hit.triangle].material];
          sum += texel_material(&set, &mt, hit.triangle, hit.b1, hit.b2).base_color.y;  // green: every quad has some
        }
      if (!on_quad) continue;
      expected.push_back(sum / (grid * grid) * kEnvironment[1]);
      rendered.push_back(image.pixel(px, py)[1]);
    }
  ASSERT_GT(rendered.size(), std::size_t(size * size / 8)) << "the quads are not in view: the test would prove nothing";
  const double n = double(rendered.size()), s_min = min_continuation(scene);
  double mean_r = 0, mean_e = 0;
  for (std::size_t k = 0; k < rendered.size(); ++k) {
    mean_r += rendered[k] / n;
    mean_e += expected[k] / n;
  }
  const double se = mean_e * std::sqrt((1.0 - s_min) / (s_min * spp * n));  // as for the textured quad, pooled
  EXPECT_NEAR(mean_r, mean_e, 5.0 * se + 0.01 * mean_e);
  double cov = 0, var_r = 0, var_e = 0;
  for (std::size_t k = 0; k < rendered.size(); ++k) {
    cov += (rendered[k] - mean_r) * (expected[k] - mean_e);
    var_r += (rendered[k] - mean_r) * (rendered[k] - mean_r);
    var_e += (expected[k] - mean_e) * (expected[k] - mean_e);
  }
  EXPECT_GT(var_e, 0.01 * mean_e * mean_e * n) << "the texture does not vary over the pixels: the test would prove nothing";
  EXPECT_GT(cov / std::sqrt(var_r * var_e), 0.9) << "the rendered pixels do not follow the texture";
}

// An emissiveTexture: a 1 m panel 0.3 m above a grey floor whose left (-x) half emits (texel 255: sRGB 1)
// and right half not (texel 0). The path tracer with light sampling (its light samples read the
// texel at the sampled point) and without (only BSDF-sampled hits, which read the texel at the hit)
// estimate the same image: their means over independent runs agree within 4.5 standard errors of
// the difference; reading the emissive factor at the light samples would double the lit half.
TEST(Textures, EmissiveTextureLightSamplesReadTheTexel) {
  Scene scene;
  SceneMaterial floor, panel;
  floor.kd = glm::vec3(0.5f);
  panel.kd = glm::vec3(0.0f);
  panel.emission = glm::vec3(2.0f);
  panel.textures.emissive = 0;
  for (int c = 0; c < 3; ++c) panel.textures.emissive_factor[c] = 2.0f;
  scene.materials = {floor, panel};
  scene.texels = {0xffffffffu, 0xff000000u};  // white, black
  TextureView v{};
  v.width = 2;
  v.height = 1;
  v.flags = BP_WRAP_CLAMP_TO_EDGE | BP_WRAP_CLAMP_TO_EDGE << BP_TEXTURE_WRAP_T_SHIFT | BP_TEXTURE_NEAREST | BP_TEXTURE_SRGB;
  texture_transform(0, 0, 0, 1, 1, v.transform);
  scene.texture_views = {v};
  scene.uv_slots = 1;
  const float f = 2.0f;  // the floor, facing +z
  scene.triangles.push_back({{{-f, -f, 0}, {f, -f, 0}, {f, f, 0}}, 0});
  scene.triangles.push_back({{{-f, -f, 0}, {f, f, 0}, {-f, f, 0}}, 0});
  const glm::vec3 q[4] = {{-0.5f, -0.5f, 0.3f}, {-0.5f, 0.5f, 0.3f}, {0.5f, 0.5f, 0.3f}, {0.5f, -0.5f, 0.3f}};  // facing -z
  for (auto [a, b, c] : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
    SceneTriangle t{{q[a], q[b], q[c]}, 1};
    const int corners[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) t.uv[0][k] = glm::vec2(q[corners[k]].x + 0.5f, 0.5f);  // u along x
    scene.triangles.push_back(t);
  }
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  scene.camera.position = glm::vec3(0.0f, 0.0f, 0.25f);  // below the panel, seeing the floor to 0.26 m
  scene.camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.yfov = 1.6f;
  const int runs = 6, spp = 32, size = 16;
  double mean[2] = {0, 0}, var[2] = {0, 0}, left[2] = {0, 0}, right[2] = {0, 0};
  for (int with_nee = 0; with_nee < 2; ++with_nee) {
    std::vector<double> m;
    for (int k = 0; k < runs; ++k) {
      const ImageRGB image = render_pt(scene, size, size, spp, 21 + 5 * k, 65536, with_nee == 1).image;
      double sum = 0.0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          sum += image.pixel(x, y)[0];
          (x < size / 2 ? left : right)[with_nee] += image.pixel(x, y)[0];
        }
      m.push_back(sum / (size * size));
    }
    for (double x : m) mean[with_nee] += x / runs;
    for (double x : m) var[with_nee] += (x - mean[with_nee]) * (x - mean[with_nee]) / (runs - 1);
  }
  const double se = std::sqrt((var[0] + var[1]) / runs);
  EXPECT_LT(se, 0.02 * mean[1]) << "too noisy to see the texel's factor 2";
  EXPECT_NEAR(mean[1], mean[0], 4.5 * se) << "with light sampling " << mean[1] << ", without " << mean[0];
  EXPECT_GT(left[1], 1.5 * right[1]) << "the floor under the lit half is not brighter";  // (the same by symmetry if not)
}

// alphaMode MASK (good/alpha-mask-quad.gltf): the top-right texel, alpha 64/255 below the cutoff 0.5,
// is no surface: its pixels see the environment itself (expected_block says what each block reads).
bool cut_away(int x, int y, bool masked) { return masked && x == 3 && y == 0; }
double expected_block(const Scene& scene, int x, int y, int c, bool masked) {
  return (cut_away(x, y, masked) ? 1.0 : texel_albedo(scene, x, y, c)) * kEnvironment[c];
}

void expect_texture_reproduced(const CombinedSettings& base, const char* what, bool masked = false) {
  const Scene scene = textured_quad(masked ? "good/alpha-mask-quad.gltf" : "good/textured-quad.gltf");
  const int runs = 8;
  std::vector<ImageRGB> images;
  for (int k = 0; k < runs; ++k) {
    CombinedSettings cs = base;
    cs.seed = 7 + 13 * std::uint32_t(k);
    images.push_back(render_combined(scene, kSize, kSize, cs).combined);
  }
  for (int y = 0; y < kTexels; ++y)
    for (int x = 0; x < kTexels; ++x)
      for (int c = 0; c < 3; ++c) {
        double mean = 0.0, var = 0.0;
        for (const ImageRGB& im : images) mean += block_mean(im, x, y, c) / runs;
        for (const ImageRGB& im : images) var += std::pow(block_mean(im, x, y, c) - mean, 2) / (runs - 1);
        const double expected = expected_block(scene, x, y, c, masked), se = std::sqrt(var / runs);
        if (!cut_away(x, y, masked)) {
          EXPECT_LT(se, 0.02 * expected) << what << ": too noisy to tell texels apart";
        }
        EXPECT_NEAR(mean, expected, 8.0 * se + 1e-4 * expected) << what << ", texel " << x << "," << y << " channel " << c;
      }
}

TEST(Textures, TexturedQuadReproducesItsTextureInRayBundlesAlone) {
  CombinedSettings cs;
  cs.pt_samples_per_round = 0;  // RB alone (--ratio 0)
  cs.rb_iterations_per_round = 16;
  cs.rounds = 64;
  cs.patch_size = 0.3f;  // patches straddle texels: their mean differs from the texels
  expect_texture_reproduced(cs, "rb alone");
}

TEST(Textures, TexturedQuadReproducesItsTextureInTheCombination) {
  CombinedSettings cs;
  cs.rounds = 128;
  cs.patch_size = 0.3f;
  expect_texture_reproduced(cs, "product weights");
}

// The path tracer through the cut-away texel: exactly L there (the camera ray passes on and leaves
// the scene); elsewhere as without the mask.
TEST(Textures, AlphaMaskCutsTheQuadInThePathTracer) {
  const Scene scene = textured_quad("good/alpha-mask-quad.gltf");
  ASSERT_TRUE(scene.has_alpha_masks());
  const int spp = 64;
  const ImageRGB image = render_pt(scene, kSize, kSize, spp, 3).image;
  const double s_min = min_continuation(scene);
  for (int y = 0; y < kTexels; ++y)
    for (int x = 0; x < kTexels; ++x)
      for (int c = 0; c < 3; ++c) {
        const double expected = expected_block(scene, x, y, c, true);
        // as in TexturedQuadReproducesItsTextureInThePathTracer
        const double se = cut_away(x, y, true) ? 1e-6 * expected
                                               : expected * std::sqrt((1.0 - s_min) / (s_min * spp * kBlock * kBlock));
        EXPECT_NEAR(block_mean(image, x, y, c), expected, 5.0 * se + 1e-6) << "texel " << x << "," << y << " channel " << c;
      }
}

// Ray bundles alone and combined: the eye's rays pass the cut texel; the patches that straddle it
// receive over the part that is there (their E_in is over its area), so the rest reads kd L as before.
TEST(Textures, AlphaMaskCutsTheQuadInRayBundlesAndTheCombination) {
  CombinedSettings cs;
  cs.pt_samples_per_round = 0;
  cs.rb_iterations_per_round = 16;
  cs.rounds = 64;
  cs.patch_size = 0.3f;
  expect_texture_reproduced(cs, "rb alone, alpha mask", true);
  cs = CombinedSettings{};
  cs.rounds = 128;
  cs.patch_size = 0.3f;
  expect_texture_reproduced(cs, "product weights, alpha mask", true);
}

}  // namespace
}  // namespace bp::test

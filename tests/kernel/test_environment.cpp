// Uniform environment light (--environment R,G,B, DESIGN.md §6): a convex Lambert object of albedo a
// under a uniform environment of radiance L reads a L (every direction above a convex surface leaves
// the scene), and the background reads L -- in the path tracer, in ray bundles alone, and in the
// product-weight combination with and without light sampling (the environment is then a technique
// of the last segment with p_L = 0).
#include "kernel/device_fixture.h"
#include "kernels/shared/bvh.h"
#include "kernels/shared/camera.h"

#include <gtest/gtest.h>
#include <cmath>
#include <vector>

namespace bp::test {
namespace {

constexpr double kAlbedo = 0.6;
const glm::vec3 kEnvironment(1.0f, 0.5f, 0.25f);
constexpr int kSize = 32;

// A unit cube of albedo kAlbedo, seen from a corner, under the environment.
Scene cube_under_environment() {
  SceneMaterial grey;
  grey.kd = glm::vec3(float(kAlbedo));
  Scene scene = make_closed_box(0.5f, grey);  // faces inwards: turn them out
  for (SceneTriangle& t : scene.triangles) std::swap(t.p[1], t.p[2]);
  scene.environment = kEnvironment;
  scene.camera.position = glm::vec3(1.6f, 1.3f, 2.2f);
  scene.camera.forward = glm::normalize(-scene.camera.position);
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 0.8f;
  return scene;
}

// Per pixel: 1 where every point of it and of its neighbours sees the cube, 0 where none does, -1
// near the silhouette (host ray casts on a 6x6 grid reaching the pixel's edges).
std::vector<int> coverage(const Scene& scene) {
  const FlatBvh bvh = build_bvh(scene.triangles);
  const CameraParams camera = pack_camera(scene.camera, kSize, kSize);
  const float3 o = make_float3(camera.position[0], camera.position[1], camera.position[2]);
  std::vector<unsigned> kinds(kSize * kSize, 0u);
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px)
      for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i) {
          const float3 d = camera_ray_direction(&camera, std::uint32_t(px), std::uint32_t(py), i / 5.0f, j / 5.0f);
          Hit hit;
          kinds[py * kSize + px] |= bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), o, d, BP_FLOAT_MAX, &hit) ? 2u : 1u;
        }
  std::vector<int> out(kSize * kSize);
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px) {
      unsigned around = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          around |= kinds[std::clamp(py + dy, 0, kSize - 1) * kSize + std::clamp(px + dx, 0, kSize - 1)];
      out[py * kSize + px] = around == 2u ? 1 : around == 1u ? 0 : -1;
    }
  return out;
}

// Mean over the cube's inner pixels of channel c, over the background pixels, and their counts.
struct Regions {
  double cube[3] = {0, 0, 0}, background[3] = {0, 0, 0};
  int cube_pixels = 0, background_pixels = 0;
};
Regions regions(const ImageRGB& image, const std::vector<int>& cover) {
  Regions r;
  for (int i = 0; i < kSize * kSize; ++i) {
    if (cover[i] < 0) continue;
    for (int c = 0; c < 3; ++c) (cover[i] ? r.cube : r.background)[c] += image.rgb[3 * i + c];
    ++(cover[i] ? r.cube_pixels : r.background_pixels);
  }
  for (int c = 0; c < 3; ++c) {
    r.cube[c] /= r.cube_pixels;
    r.background[c] /= r.background_pixels;
  }
  return r;
}

// The path tracer: a sample of a cube pixel is L (the walk continues, with probability s = a, and its
// cosine-sampled direction leaves the scene with weight f cos / (s p) = 1) or 0, so each pixel is within
// 5 standard errors sqrt(a (1 - a) / spp) L of a L; the background is L.
TEST(Environment, ConvexLambertObjectReadsAlbedoTimesRadianceInThePathTracer) {
  const Scene scene = cube_under_environment();
  const std::vector<int> cover = coverage(scene);
  const int spp = 256;
  const ImageRGB image = render_pt(scene, kSize, kSize, spp, 5).image;
  int cube_pixels = 0;
  for (int i = 0; i < kSize * kSize; ++i) {
    if (cover[i] < 0) continue;
    cube_pixels += cover[i];
    for (int c = 0; c < 3; ++c) {
      const double l = kEnvironment[c];
      if (cover[i])
        ASSERT_NEAR(image.rgb[3 * i + c], kAlbedo * l, 5.0 * std::sqrt(kAlbedo * (1 - kAlbedo) / spp) * l + 1e-5)
            << "cube pixel " << i << " channel " << c;
      else
        ASSERT_NEAR(image.rgb[3 * i + c], l, 1e-5 * l) << "background pixel " << i;
    }
  }
  EXPECT_GT(cube_pixels, kSize * kSize / 8) << "the cube is not in view: the test would prove nothing";
}

// Ray bundles and the combination: the cube's mean over independent runs against a L (a t-test at
// 4.5 standard errors, the error's own standard error asserted below 1 %), the background L.
void expect_cube_reads_albedo(const CombinedSettings& base, const char* what, bool faint_light = false) {
  Scene scene = cube_under_environment();
  if (faint_light) {  // about 1e-6 W/m^2 at the cube: light sampling acts, and adds nothing to see
    ScenePunctualLight point;
    point.position = glm::vec3(0.0f, 30.0f, 0.0f);
    point.intensity = glm::vec3(1e-3f);
    scene.lights = {point};
  }
  const std::vector<int> cover = coverage(scene);
  const int runs = 6;
  std::vector<Regions> r;
  for (int k = 0; k < runs; ++k) {
    CombinedSettings cs = base;
    cs.seed = 11 + 17 * std::uint32_t(k);
    r.push_back(regions(render_combined(scene, kSize, kSize, cs).combined, cover));
  }
  for (int c = 0; c < 3; ++c) {
    double mean = 0.0, var = 0.0, background = 0.0;
    for (const Regions& x : r) mean += x.cube[c] / runs;
    for (const Regions& x : r) var += (x.cube[c] - mean) * (x.cube[c] - mean) / (runs - 1);
    for (const Regions& x : r) background += x.background[c] / runs;
    const double expected = kAlbedo * kEnvironment[c], se = std::sqrt(var / runs);
    EXPECT_LT(se, 0.01 * expected) << what << ": too noisy to see a few percent";
    EXPECT_NEAR(mean, expected, 4.5 * se + 1e-4 * expected) << what << ", channel " << c;
    EXPECT_NEAR(background, kEnvironment[c], 1e-4 * kEnvironment[c]) << what << ", background, channel " << c;
  }
}

TEST(Environment, ConvexLambertObjectReadsAlbedoTimesRadianceInRayBundlesAlone) {
  CombinedSettings cs;
  cs.pt_samples_per_round = 0;  // RB alone (--ratio 0)
  cs.rb_iterations_per_round = 16;
  cs.rounds = 16;
  expect_cube_reads_albedo(cs, "rb alone");
}

TEST(Environment, ConvexLambertObjectReadsAlbedoTimesRadianceInTheCombination) {
  CombinedSettings cs;
  cs.rounds = 32;
  expect_cube_reads_albedo(cs, "product weights");
  cs.light_sampling = true;  // with nothing else to sample the environment is still p_L = 0 (no light: off)
  expect_cube_reads_albedo(cs, "product weights, light sampling on without a light");
}

// With light sampling acting (a faint point light far off, a millionth of the environment's light):
// the environment is then split between PT's BSDF samples and RB's bundles as a last segment with
// p_L = 0, at the eye vertex (shared or PT's alone) and after.
TEST(Environment, ConvexLambertObjectReadsAlbedoTimesRadianceWithLightSamplingActing) {
  CombinedSettings cs;
  cs.rounds = 32;
  cs.light_sampling = true;
  cs.light_rate = 0.5f;
  for (bool shared : {false, true}) {
    cs.eye_direct_shared = shared;
    expect_cube_reads_albedo(cs, shared ? "light sampling, eye direct shared" : "light sampling, eye direct pt", true);
  }
}

}  // namespace
}  // namespace bp::test

// Environment light (--environment R,G,B and FILE.exr, docs/design.md §6): a convex Lambert object of
// albedo a under a uniform environment of radiance L reads a L (every direction above a convex
// surface leaves the scene), and the background reads L -- in the path tracer, in ray bundles alone,
// and in the product-weight combination with and without light sampling (the environment is then a
// light, a technique of the last segment with its own p_L). The same with a constant map in place of
// the uniform radiance, and a map with an analytic answer: a plane facing up under a graded sky
// reads a E_up / pi, with light sampling on and off.
#include "environment_maps.h"
#include "kernel/device_fixture.h"
#include "kernels/shared/bvh.h"
#include "kernels/shared/camera.h"

#include <gtest/gtest.h>
#include <array>
#include <cmath>
#include <vector>

namespace bp::test {
namespace {

constexpr double kAlbedo = 0.6;
const glm::vec3 kEnvironment(1.0f, 0.5f, 0.25f);
constexpr int kSize = 32;

// A unit cube of albedo kAlbedo, seen from a corner, under the environment: the uniform radiance, or
// (as_map) a constant 4 x 2 map of it.
Scene cube_under_environment(bool as_map = false) {
  SceneMaterial grey;
  grey.kd = glm::vec3(float(kAlbedo));
  Scene scene = make_closed_box(0.5f, grey);  // faces inwards: turn them out
  for (SceneTriangle& t : scene.triangles) std::swap(t.p[1], t.p[2]);
  scene.environment = kEnvironment;
  if (as_map) {
    scene.environment = glm::vec3(0.0f);
    scene.environment_image = std::make_shared<const EnvironmentImage>(constant_environment(4, 2, &kEnvironment[0]));
  }
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
void expect_pt_cube_reads_albedo(const Scene& scene) {
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

TEST(Environment, ConvexLambertObjectReadsAlbedoTimesRadianceInThePathTracer) {
  expect_pt_cube_reads_albedo(cube_under_environment());
}

// Ray bundles and the combination: the cube's mean over independent runs against a L (a t-test at
// 4.5 standard errors, the error's own standard error asserted below 1 %), the background L.
void expect_cube_reads_albedo(const CombinedSettings& base, const char* what, bool faint_light = false,
                              bool as_map = false) {
  Scene scene = cube_under_environment(as_map);
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
  cs.light_sampling = true;  // the environment is the only light to sample
  expect_cube_reads_albedo(cs, "product weights, light sampling the environment alone");
}

// With light sampling acting (a faint point light far off, a millionth of the environment's light):
// the environment is then split between the four techniques of a last segment with its own p_L, at
// the eye vertex (shared or PT's alone) and after.
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

// --environment FILE.exr with a constant map renders as --environment R,G,B of the same radiance:
// both read a L on the cube and L in the background, in the path tracer and in the combination (its
// sampling density differs from the uniform one's; the image may not), and the two path-traced
// images agree pixel by pixel within the noise (a z-test of their mean difference over the cube).
TEST(Environment, ConstantMapRendersAsTheUniformRadiance) {
  const Scene map_scene = cube_under_environment(true);
  expect_pt_cube_reads_albedo(map_scene);
  CombinedSettings cs;
  cs.rounds = 32;
  cs.light_sampling = true;
  cs.light_rate = 0.5f;
  expect_cube_reads_albedo(cs, "constant map, light sampling", false, true);
  const std::vector<int> cover = coverage(map_scene);
  const ImageRGB a = render_pt(cube_under_environment(), kSize, kSize, 128, 7).image;
  const ImageRGB b = render_pt(map_scene, kSize, kSize, 128, 8).image;
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (int i = 0; i < kSize * kSize; ++i) {
      if (cover[i] != 1) continue;
      const double d = double(a.rgb[3 * i + c]) - b.rgb[3 * i + c];
      sum += d;
      sum2 += d * d;
      ++n;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, 0.0, 4.5 * se + 1e-6) << "channel " << c;
    EXPECT_LT(se, 0.01 * kAlbedo * kEnvironment[c]);
  }
}

// A square plane facing +Y, seen from above so that it fills the view, under the graded sky (its
// upper half varies by column, its lower half is 15x brighter and below the plane): every pixel
// reads a E_up / pi, E_up the irradiance of the upper half alone.
Scene plane_under_graded_sky() {
  SceneMaterial grey;
  grey.kd = glm::vec3(float(kAlbedo));
  Scene scene;
  scene.materials.push_back(grey);
  const float h = 1.5f;
  const glm::vec3 a(-h, 0, -h), b(-h, 0, h), c(h, 0, h), d(h, 0, -h);
  scene.triangles.push_back({{a, b, c}, 0});  // counter-clockwise seen from above: facing +Y
  scene.triangles.push_back({{a, c, d}, 0});
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  scene.environment_image = std::make_shared<const EnvironmentImage>(graded_sky());
  scene.camera.position = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.yfov = 0.8f;
  return scene;
}

double plane_expected(int c) { return kAlbedo * upward_irradiance(graded_sky(), c) / M_PI; }

// The path tracer, with light sampling (the map importance-sampled, and MIS with the BSDF's samples)
// and without (BSDF samples alone): each image's mean within 5 standard errors of the pixels' spread.
TEST(Environment, PlaneUnderAGradedSkyReadsAlbedoTimesItsUpperIrradianceInThePathTracer) {
  const Scene scene = plane_under_graded_sky();
  for (bool light_sampling : {true, false}) {
    const ImageRGB image = render_pt(scene, kSize, kSize, 64, 3, 65536, light_sampling).image;
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0, sum2 = 0.0;
      for (int i = 0; i < kSize * kSize; ++i) {
        sum += image.rgb[3 * i + c];
        sum2 += double(image.rgb[3 * i + c]) * image.rgb[3 * i + c];
      }
      const int n = kSize * kSize;
      const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
      EXPECT_LT(se, 0.01 * plane_expected(c));
      EXPECT_NEAR(mean, plane_expected(c), 5.0 * se) << (light_sampling ? "light sampling" : "BSDF sampling alone")
                                                    << ", channel " << c;
    }
  }
}

// Ray bundles alone and the combination, with light sampling (eye direct shared and PT's alone):
// the image mean over independent runs against a E_up / pi (a t-test at 4.5 standard errors).
TEST(Environment, PlaneUnderAGradedSkyReadsAlbedoTimesItsUpperIrradianceInTheCombination) {
  const Scene scene = plane_under_graded_sky();
  // One bundle direction lights the whole plane at once: RB's level noise needs many iterations
  // (large patches keep them cheap; the plane's value is the same on every patch).
  CombinedSettings rb_alone;
  rb_alone.pt_samples_per_round = 0;
  rb_alone.rb_iterations_per_round = 16;
  rb_alone.rounds = 192;
  rb_alone.patch_size = 0.3f;
  CombinedSettings shared;
  shared.rounds = 256;
  shared.patch_size = 0.3f;
  shared.light_sampling = true;
  shared.light_rate = 0.5f;
  shared.eye_direct_shared = true;
  CombinedSettings pt_eye = shared;
  pt_eye.eye_direct_shared = false;
  const std::pair<const char*, CombinedSettings> cases[] = {
      {"rb alone", rb_alone}, {"light sampling, eye direct shared", shared}, {"light sampling, eye direct pt", pt_eye}};
  for (const auto& [what, base] : cases) {
    const int runs = 8;
    std::vector<std::array<double, 3>> means;
    for (int k = 0; k < runs; ++k) {
      CombinedSettings cs = base;
      cs.seed = 5 + 13 * std::uint32_t(k);
      const ImageRGB image = render_combined(scene, kSize, kSize, cs).combined;
      std::array<double, 3> m{0, 0, 0};
      for (int i = 0; i < kSize * kSize; ++i)
        for (int c = 0; c < 3; ++c) m[c] += image.rgb[3 * i + c] / double(kSize * kSize);
      means.push_back(m);
    }
    for (int c = 0; c < 3; ++c) {
      double mean = 0.0, var = 0.0;
      for (const auto& m : means) mean += m[c] / runs;
      for (const auto& m : means) var += (m[c] - mean) * (m[c] - mean) / (runs - 1);
      const double se = std::sqrt(var / runs);
      EXPECT_LT(se, 0.01 * plane_expected(c)) << what;
      EXPECT_NEAR(mean, plane_expected(c), 4.5 * se + 1e-4 * plane_expected(c)) << what << ", channel " << c;
    }
  }
}

// A corner -- a floor facing up and a wall facing it -- under the graded sky: light reaches the eye
// after two bounces too, so RB's direct chain weights the sky it receives with the environment's p_L
// as the last segment of a longer path. The combination (light sampling, the eye vertex's direct
// light PT's alone or shared) against the path tracer: the image means over independent runs agree
// within 4.5 standard errors of their difference.
TEST(Environment, CornerUnderAGradedSkyInTheCombinationAgreesWithThePathTracer) {
  SceneMaterial grey;
  grey.kd = glm::vec3(float(kAlbedo));
  Scene scene;
  scene.materials.push_back(grey);
  const glm::vec3 f0(-0.5f, 0, -0.5f), f1(-0.5f, 0, 0.5f), f2(0.5f, 0, 0.5f), f3(0.5f, 0, -0.5f);
  const glm::vec3 w0(-0.5f, 0, -0.5f), w1(0.5f, 0, -0.5f), w2(0.5f, 1, -0.5f), w3(-0.5f, 1, -0.5f);
  scene.triangles = {{{f0, f1, f2}, 0}, {{f0, f2, f3}, 0}, {{w0, w1, w2}, 0}, {{w0, w2, w3}, 0}};  // up, and +Z
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  scene.environment_image = std::make_shared<const EnvironmentImage>(graded_sky());
  scene.camera.position = glm::vec3(0.3f, 0.9f, 1.4f);
  scene.camera.forward = glm::normalize(glm::vec3(0.0f, 0.3f, -0.5f) - scene.camera.position);
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 0.9f;
  const int n = kSize * kSize;
  const auto image_mean = [&](const ImageRGB& image) {
    std::array<double, 3> m{0, 0, 0};
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) m[c] += image.rgb[3 * i + c] / n;
    return m;
  };
  for (bool shared : {false, true}) {
    // per run: the combination's image mean minus an independent path-traced one's
    const int runs = 8;
    std::vector<std::array<double, 3>> differences;
    double level = 0.0;
    for (int k = 0; k < runs; ++k) {
      CombinedSettings cs;
      cs.rounds = 192;
      cs.light_sampling = true;
      cs.light_rate = 0.5f;
      cs.eye_direct_shared = shared;
      cs.seed = 3 + 19 * std::uint32_t(k);
      const std::array<double, 3> combined = image_mean(render_combined(scene, kSize, kSize, cs).combined);
      const std::array<double, 3> pt = image_mean(render_pt(scene, kSize, kSize, 192, 101 + std::uint32_t(k)).image);
      differences.push_back({combined[0] - pt[0], combined[1] - pt[1], combined[2] - pt[2]});
      level += pt[1] / runs;
    }
    for (int c = 0; c < 3; ++c) {
      double mean = 0.0, var = 0.0;
      for (const auto& d : differences) mean += d[c] / runs;
      for (const auto& d : differences) var += (d[c] - mean) * (d[c] - mean) / (runs - 1);
      const double se = std::sqrt(var / runs);
      EXPECT_LT(se, 0.01 * level * (c == 0 ? 2.0 : c == 1 ? 1.0 : 0.5));  // the sky's colour is (1, 1/2, 1/4)
      EXPECT_NEAR(mean, 0.0, 4.5 * se) << (shared ? "eye direct shared" : "eye direct pt") << ", channel " << c;
    }
  }
}

}  // namespace
}  // namespace bp::test

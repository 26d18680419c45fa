// glTF normal maps in the kernels (docs/design.md §6): the shading normal per texel in the path tracer's
// walk and in RB's eye gather, the weights' inputs patch-level. A flat map renders as no map; a
// tilted constant map scales a Lambert quad's direct light by the cosine ratio the map predicts; and
// the combination over a box of bumpy walls agrees with the path tracer.
#include "kernel/device_fixture.h"
#include "kernel/region_test.h"
#include "scene/tangents.h"
#include "scene/textures.h"
#include "stats.h"

#include "kernels/shared/normal_map.h"

#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>

namespace bp::test {
namespace {

// Gives `material` of `scene` a `width` x `height` normal map (RGB bytes, linear, bilinear, repeat)
// of `scale`, and its triangles tangents: T = `tangent` where given, else any one in the surface,
// handedness `w`; uv from the position along T and the bitangent, one texture per metre.
// `rotation` (radians): KHR_texture_transform's, about the uv origin.
void add_normal_map(Scene& scene, std::uint32_t material, int width, int height, const std::vector<unsigned>& rgb,
                    float scale, float w, glm::vec3 tangent = glm::vec3(0.0f), float rotation = 0.0f) {
  TextureView v{};
  v.first_texel = std::uint32_t(scene.texels.size());
  v.width = std::uint32_t(width);
  v.height = std::uint32_t(height);
  v.flags = BP_WRAP_REPEAT | BP_WRAP_REPEAT << BP_TEXTURE_WRAP_T_SHIFT;
  texture_transform(0.0f, 0.0f, rotation, 1.0f, 1.0f, v.transform);
  for (int i = 0; i < width * height; ++i)
    scene.texels.push_back(rgb[3 * i] | rgb[3 * i + 1] << 8 | rgb[3 * i + 2] << 16 | 0xff000000u);
  scene.texture_views.push_back(v);
  scene.uv_slots = 1;
  scene.materials[material].textures.normal = std::uint32_t(scene.texture_views.size() - 1);
  scene.materials[material].textures.normal_scale = scale;
  for (SceneTriangle& t : scene.triangles) {
    if (t.material != material) continue;
    const glm::vec3 n = glm::normalize(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
    const glm::vec3 tt = tangent == glm::vec3(0.0f) ? any_tangent(n) : tangent;
    const glm::vec3 b = w * glm::cross(n, tt);
    for (int k = 0; k < 3; ++k) {
      t.tangent[k] = glm::vec4(tt, w);
      t.uv[0][k] = glm::vec2(glm::dot(t.p[k], tt), -glm::dot(t.p[k], b));  // B points up the image: v falls along it
    }
  }
}

// ---------------------------------------------------------------- a Lambert quad under a sun

constexpr int kQuadSize = 16;
constexpr double kKd = 0.5;
const glm::dvec3 kToSun = glm::normalize(glm::dvec3(0.6, 0.3, 1.0));

// A 2 m quad in z = 0 facing +z filling the view from (0, 0, 3), lit by a sun of 1 W/m^2: nothing
// else, so every pixel reads kd/pi cos(theta_shading), exactly, with light sampling.
Scene sunlit_quad() {
  Scene scene;
  SceneMaterial m;
  m.kd = glm::vec3(float(kKd));
  scene.materials = {m};
  const glm::vec3 p[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  scene.triangles.push_back({{p[0], p[1], p[2]}, 0});
  scene.triangles.push_back({{p[0], p[2], p[3]}, 0});
  for (const glm::vec3& q : p) scene.bounds.grow(q);
  ScenePunctualLight sun;
  sun.kind = ScenePunctualLight::Kind::directional;
  sun.direction = -glm::vec3(kToSun);
  sun.intensity = glm::vec3(1.0f);
  scene.lights = {sun};
  scene.camera.position = glm::vec3(0.0f, 0.0f, 3.0f);
  scene.camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.yfov = 0.6f;
  return scene;
}

// Every pixel of `image` within 5 standard errors of `expected` (the spread of its pixels over
// `samples` each, plus float rounding): a z-test per channel of the image mean and of each pixel.
void expect_uniform_image(const ImageRGB& image, double expected, double samples, const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, sum2 = 0.0;
    const int n = image.width * image.height;
    for (int i = 0; i < n; ++i) {
      const double v = image.pixel(i % image.width, i / image.width)[c];
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    const double tolerance = 5.0 * sd / std::sqrt(double(n)) + 2e-4 * expected;
    EXPECT_NEAR(mean, expected, tolerance) << what << ", channel " << c << " (" << samples << " samples a pixel)";
    for (int i = 0; i < n; ++i)
      ASSERT_NEAR(image.pixel(i % image.width, i / image.width)[c], expected, 5.0 * sd + 2e-4 * expected)
          << what << ", pixel " << i;
  }
}

TEST(NormalMaps, TiltedConstantMapScalesTheSunlitQuadByTheCosineRatio) {
  const unsigned texel[3] = {200, 90, 230};
  const float scale = 0.8f, w = -1.0f;  // w -1: B = -cross(N, T) = -y, so the map's green tilts towards +y
  // n_ts = normalize((2 rgb/255 - 1)(scale, scale, 1)); world N' = normalize(x T + y B + z N), T = +x, B = -y
  const glm::dvec3 n_ts((2.0 * texel[0] / 255.0 - 1.0) * scale, (2.0 * texel[1] / 255.0 - 1.0) * scale,
                        2.0 * texel[2] / 255.0 - 1.0);
  const glm::dvec3 mapped = glm::normalize(glm::dvec3(n_ts.x, -n_ts.y, n_ts.z));
  const double flat_l = kKd / M_PI * kToSun.z, mapped_l = kKd / M_PI * glm::dot(mapped, kToSun);
  std::printf("[normal maps] sunlit quad: flat %.5f, mapped %.5f (ratio %.4f)\n", flat_l, mapped_l, mapped_l / flat_l);
  ASSERT_GT(std::fabs(mapped_l / flat_l - 1.0), 0.1) << "the map must change the light enough to see";

  Scene flat = sunlit_quad(), tilted = sunlit_quad();
  add_normal_map(tilted, 0, 1, 1, {texel[0], texel[1], texel[2]}, scale, w, glm::vec3(1, 0, 0));
  const int spp = 16;
  expect_uniform_image(render_pt(flat, kQuadSize, kQuadSize, spp, 5).image, flat_l, spp, "PT, no map");
  expect_uniform_image(render_pt(tilted, kQuadSize, kQuadSize, spp, 5).image, mapped_l, spp, "PT, tilted map");

  // RB's eye gather reflects its patches' sun with the texel's normal: with the eye vertex's direct
  // light shared, a delta light's share is fixed, c/(c + 1) to RB (c = N2/N1 x rate), the rest to PT.
  CombinedSettings cs;
  cs.light_sampling = true;
  cs.eye_direct_shared = true;
  cs.rounds = 8;
  cs.patch_size = 0.5f;
  const CombinedRun run = render_combined(tilted, kQuadSize, kQuadSize, cs);
  const double rb_share = 4.0 / 5.0;
  expect_uniform_image(run.rb, rb_share * mapped_l, double(cs.rounds), "RB layer, tilted map");
  expect_uniform_image(run.pt, (1.0 - rb_share) * mapped_l, double(cs.rounds), "PT layer, tilted map");
  expect_uniform_image(run.combined, mapped_l, double(cs.rounds), "combined, tilted map");
}

// A view behind the mapped normal (a normal map, or a smooth-shaded rim, seen at a grazing angle):
// the normal map tilts the shading normal 70 degrees away from a camera that looks along the floor,
// so every pixel's view is behind it, though in front of the floor. Lambert's term does not depend
// on the view, so each pixel still reads kd/pi cos(theta_shading) of the sun, in both estimators
// (brdf.h, bsdf_shading_normal); it used to be black.
TEST(NormalMaps, AViewBehindTheMappedNormalStillSeesTheLambertFloor) {
  Scene floor = sunlit_quad();
  const glm::vec3 p[4] = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
  floor.triangles = {{{p[0], p[1], p[2]}, 0}, {{p[0], p[2], p[3]}, 0}};
  floor.bounds = {};
  for (const glm::vec3& q : p) floor.bounds.grow(q);
  floor.camera.position = glm::vec3(0.0f, 0.0f, 0.5f);  // 0.5 m above the floor, 27 degrees down
  floor.camera.forward = glm::normalize(glm::vec3(1.0f, 0.0f, -0.5f));
  floor.camera.up = glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f));
  floor.camera.yfov = 0.3f;                             // the top row 18 degrees down: all floor
  const unsigned texel[3] = {247, 128, 171};            // n_ts about (0.94, 0, 0.34): 70 degrees toward +x
  add_normal_map(floor, 0, 1, 1, {texel[0], texel[1], texel[2]}, 1.0f, 1.0f, glm::vec3(1, 0, 0));
  const glm::dvec3 mapped =
      glm::normalize(glm::dvec3(2.0 * texel[0] / 255.0 - 1.0, 2.0 * texel[1] / 255.0 - 1.0, 2.0 * texel[2] / 255.0 - 1.0));
  const glm::dvec3 top_view = -glm::normalize(glm::dvec3(1.0, 0.0, -0.5 + std::tan(0.15)));
  ASSERT_LT(glm::dot(mapped, top_view), -0.5) << "the case: every view behind the mapped normal";
  const double l = kKd / M_PI * glm::dot(mapped, kToSun);
  const int spp = 16;
  expect_uniform_image(render_pt(floor, kQuadSize, kQuadSize, spp, 9).image, l, spp, "PT, view behind the normal");
  CombinedSettings cs;
  cs.light_sampling = true;
  cs.eye_direct_shared = true;
  cs.rounds = 8;
  cs.patch_size = 2.0f;
  const CombinedRun run = render_combined(floor, kQuadSize, kQuadSize, cs);
  const double rb_share = 4.0 / 5.0;  // as in the test above
  expect_uniform_image(run.rb, rb_share * l, double(cs.rounds), "RB layer, view behind the normal");
  expect_uniform_image(run.pt, (1.0 - rb_share) * l, double(cs.rounds), "PT layer, view behind the normal");
}

// KHR_texture_transform turns the map's slopes with its image: the same texel through a uv rotated by
// a quarter turn tilts the shading normal a quarter turn about N (normal_map_untransformed).
TEST(NormalMaps, ARotatedMapsSlopesTurnWithItsImage) {
  const unsigned texel[3] = {230, 128, 200};  // tilted along the image's x
  const float scale = 1.0f, w = 1.0f;         // T = +x, B = cross(N, T) = +y
  const glm::dvec3 n_ts((2.0 * texel[0] / 255.0 - 1.0) * scale, (2.0 * texel[1] / 255.0 - 1.0) * scale,
                        2.0 * texel[2] / 255.0 - 1.0);
  // A quarter turn: u' = -v, v' = u, so in image axes (x = u, y = -v) x' = y and y' = -x: the image's
  // x' runs along the surface's +y and y' along -x, and N' = x_ts (+y) + y_ts (-x) + z_ts N.
  const glm::dvec3 rotated = glm::normalize(glm::dvec3(-n_ts.y, n_ts.x, n_ts.z));
  const glm::dvec3 unrotated = glm::normalize(n_ts);
  const double rotated_l = kKd / M_PI * glm::dot(rotated, kToSun), unrotated_l = kKd / M_PI * glm::dot(unrotated, kToSun);
  std::printf("[normal maps] rotated map: %.5f, unrotated %.5f\n", rotated_l, unrotated_l);
  ASSERT_GT(std::fabs(rotated_l / unrotated_l - 1.0), 0.1) << "the turn must change the light enough to see";

  Scene scene = sunlit_quad();
  add_normal_map(scene, 0, 1, 1, {texel[0], texel[1], texel[2]}, scale, w, glm::vec3(1, 0, 0), float(M_PI / 2.0));
  const int spp = 16;
  expect_uniform_image(render_pt(scene, kQuadSize, kQuadSize, spp, 7).image, rotated_l, spp, "PT, rotated map");
}

// ---------------------------------------------------------------- the glossy light box, walls mapped

TEST(NormalMaps, FlatMapRendersAsNoMap) {
  const Scene plain = make_glossy_light_box();
  Scene mapped = plain;
  add_normal_map(mapped, 0, 1, 1, {128, 128, 255}, 1.0f, 1.0f);  // n_ts = (1/255, 1/255, 1): 0.3 degrees off
  // 8 runs each, the same seeds: the same paths up to where a 0.3 degree bend changes a hit, so the
  // difference is far below each one's noise, which the t-tests (blocks and image level) use
  const int runs = 8, spp = 64;
  const Sample a = independent_runs(runs, [&](std::uint32_t seed) { return render_pt(plain, kSize, kSize, spp, seed).image; });
  const Sample b = independent_runs(runs, [&](std::uint32_t seed) { return render_pt(mapped, kSize, kSize, spp, seed).image; });
  std::printf("[normal maps] flat map vs none: image mean %.6f vs %.6f (%+.3f %%, se %.3f %%)\n", b.level, a.level,
              100.0 * (b.level / a.level - 1.0), 100.0 * a.level_se / a.level);
  for (const std::string& d : significant_differences(b, a, runs)) ADD_FAILURE() << d;
  EXPECT_NEAR(b.level, a.level, 0.01 * a.level);
}

// A 4 x 4 map of bumps tilted up to 35 degrees every which way (a fixed pattern), on every wall.
std::vector<unsigned> bumpy_texels() {
  std::vector<unsigned> rgb;
  for (int i = 0; i < 16; ++i) {
    const double phi = 2.399963 * i, tilt = 0.6 * ((i * 7) % 16) / 15.0;  // golden-angle turns
    const glm::dvec3 n(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt));
    for (int c = 0; c < 3; ++c) rgb.push_back(unsigned(std::lround((n[c] * 0.5 + 0.5) * 255.0)));
  }
  return rgb;
}

TEST(NormalMaps, TheCombinationWithBumpyWallsAgreesWithThePathTracer) {
  Scene scene = make_glossy_light_box();
  add_normal_map(scene, 0, 4, 4, bumpy_texels(), 1.0f, -1.0f);  // with handedness -1
  const int runs = 8;
  std::vector<ImageRGB> pt_images, combined_images;
  for (int k = 0; k < runs; ++k) {
    const std::uint32_t seed = std::uint32_t(2000 + 37 * k);
    pt_images.push_back(render_pt(scene, kSize, kSize, 256, seed).image);
    CombinedSettings cs;
    cs.light_sampling = true;
    cs.eye_direct_shared = true;
    cs.rounds = 64;  // 64 spp + 256 iterations
    cs.patch_size = 0.05f;
    cs.seed = seed + 1;
    combined_images.push_back(render_combined(scene, kSize, kSize, cs).combined);
  }
  std::size_t next = 0;
  const Sample pt = independent_runs(runs, [&](std::uint32_t) { return pt_images[next++]; });
  next = 0;
  const Sample combined = independent_runs(runs, [&](std::uint32_t) { return combined_images[next++]; });
  std::printf("[normal maps] bumpy box: combined %.5f +- %.5f, PT %.5f +- %.5f (%+.2f %%)\n", combined.level,
              combined.level_se, pt.level, pt.level_se, 100.0 * (combined.level / pt.level - 1.0));
  for (const std::string& d : significant_differences(combined, pt, runs)) ADD_FAILURE() << d;
  EXPECT_LT(std::hypot(combined.level_se, pt.level_se) / pt.level, 0.01) << "too noisy to see a 3 % bias";
}

// The shared code on the host: the tangent-space normal and its frame (normal_map.h).
TEST(NormalMaps, TangentSpaceNormalAndItsFrame) {
  Texel flat{0.5f, 0.5f, 1.0f, 1.0f};
  const float3 up = normal_map_tangent_space(flat, 3.0f);
  EXPECT_NEAR(up.z, 1.0f, 1e-6f);
  Texel tilted{1.0f, 0.5f, 1.0f, 1.0f};  // x 1 scaled by 0.5, z 1: 26.6 degrees towards T
  const float3 n_ts = normal_map_tangent_space(tilted, 0.5f);
  EXPECT_NEAR(n_ts.x, 0.5f / std::sqrt(1.25f), 1e-6f);
  const float3 n = make_float3(0, 0, 1), t = make_float3(1, 0, 0.3f);  // t not orthogonal: Gram-Schmidt
  const float3 world = normal_map_to_world(n, t, 1.0f, make_float3(0.6f, 0.0f, 0.8f));
  EXPECT_NEAR(world.x, 0.6f, 1e-6f);
  EXPECT_NEAR(world.z, 0.8f, 1e-6f);
  const float3 y_plus = normal_map_to_world(n, make_float3(1, 0, 0), 1.0f, make_float3(0, 0.6f, 0.8f));
  const float3 y_minus = normal_map_to_world(n, make_float3(1, 0, 0), -1.0f, make_float3(0, 0.6f, 0.8f));
  EXPECT_NEAR(y_plus.y, 0.6f, 1e-6f);   // B = cross(N, T) = +y
  EXPECT_NEAR(y_minus.y, -0.6f, 1e-6f);  // B = -cross(N, T)
  const float3 no_frame = normal_map_to_world(n, make_float3(0, 0, 2), 1.0f, make_float3(0.6f, 0.0f, 0.8f));
  EXPECT_EQ(no_frame.z, 1.0f);  // t along n: no frame, the normal itself
}

// A height field h = g' . (x', y') painted in the transformed image, read back on a surface whose
// frame is T = +x, B = +y (image axes x = u, y = -v): its slopes over the surface, by finite
// differences, against normal_map_untransformed's turn of the map's normal. Rotations and mirrors
// keep the slopes' size and turn them exactly; a uniform scale keeps the map's tilt (tangents keep
// only directions) and its direction.
TEST(NormalMaps, ATransformedMapsNormalTurnsAsItsImage) {
  const glm::dvec2 slope_in_image(0.3, -0.45);  // dh/dx', dh/dy'
  const float3 n_image = make_float3(float(-slope_in_image.x), float(-slope_in_image.y), 1.0f);
  struct Case {
    float rotation, scale_u, scale_v;
  };
  for (const Case c : {Case{0.0f, 1, 1}, Case{0.7f, 1, 1}, Case{-2.1f, 1, 1}, Case{3.0f, -1, 1}, Case{1.2f, 1, -1},
                       Case{0.4f, 2.5f, 2.5f}}) {
    float transform[6];
    texture_transform(0.2f, -0.1f, c.rotation, c.scale_u, c.scale_v, transform);
    auto height = [&](double x, double y) {  // the surface point (x, y) -> uv -> uv' -> image' axes
      const double u = x, v = -y;
      const double u2 = transform[0] * u + transform[2] * v + transform[4];
      const double v2 = transform[1] * u + transform[3] * v + transform[5];
      return slope_in_image.x * u2 + slope_in_image.y * (-v2);
    };
    const double e = 1e-3;
    glm::dvec2 slope((height(0.3 + e, 0.2) - height(0.3 - e, 0.2)) / (2 * e),
                     (height(0.3, 0.2 + e) - height(0.3, 0.2 - e)) / (2 * e));
    const double size = std::fabs(c.scale_u);  // the uniform scale that steepens the field, not the map
    slope /= size;
    const float3 turned = normal_map_untransformed(transform, n_image);
    const std::string what = "rotation " + std::to_string(c.rotation) + ", scale " + std::to_string(c.scale_u) +
                             " x " + std::to_string(c.scale_v);
    EXPECT_NEAR(turned.x, -slope.x, 1e-5) << what;
    EXPECT_NEAR(turned.y, -slope.y, 1e-5) << what;
    EXPECT_EQ(turned.z, 1.0f) << what;
  }
}

}  // namespace
}  // namespace bp::test

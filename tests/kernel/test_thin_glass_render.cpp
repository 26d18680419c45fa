// Thin glass (KHR_materials_transmission, thin-walled; docs/design.md §11) on the test device: a pane is
// a filter on a segment. PT's shadow rays and its walk pass it attenuated by (1 - F) baseColor T
// (closed forms: a sun's direct light, exact; a uniform sky's, by its cosine-weighted Schlick
// factor), and the combination with a pane -- RB's bundles and eye rays through it, its light samples
// through it, the pane's mirror PT's alone -- agrees with the path tracer.
#include "kernel/device_fixture.h"
#include "kernel/power_test.h"
#include "kernel/region_test.h"
#include "kernels/shared/thin_glass.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

constexpr double kAlbedo = 0.6, kTheta = 0.9;  // the floor's, and the sun's angle from the zenith
constexpr float kIor = 1.5f;
const glm::vec3 kTint(0.9f, 0.6f, 0.3f);           // the pane's baseColor (transmission 1)
const glm::vec3 kIrradiance(2.0f, 1.5f, 1.0f);    // W/m^2 of the sun

SceneMaterial thin_pane(const glm::vec3& tint, float transmission, float ior, const glm::vec3& rest) {
  SceneMaterial m;
  m.kd = rest;  // the opaque rest, as the loader leaves it (scaled by 1 - transmission)
  m.transmission = transmission;
  m.transmission_tint = tint;
  m.ior = ior;
  m.double_sided = true;
  return m;
}

// A 4 m grey floor at y = 0 facing +y, seen from 1 m above looking straight down; `with_pane`: a
// pane 2 pane_half_size wide at y = 1.5 above the camera, which the light paths to the floor cross.
Scene floor_under_a_pane(bool with_pane, float pane_half_size = 20.0f) {
  Scene scene;
  SceneMaterial grey;
  grey.kd = glm::vec3(float(kAlbedo));
  scene.materials = {grey, thin_pane(kTint, 1.0f, kIor, glm::vec3(0.0f))};
  const float h = 2.0f, p = pane_half_size, y = 1.5f;  // counter-clockwise seen from +y
  scene.triangles.push_back({{{-h, 0, -h}, {-h, 0, h}, {h, 0, h}}, 0});
  scene.triangles.push_back({{{-h, 0, -h}, {h, 0, h}, {h, 0, -h}}, 0});
  if (with_pane) {
    scene.triangles.push_back({{{-p, y, -p}, {-p, y, p}, {p, y, p}}, 1});
    scene.triangles.push_back({{{-p, y, -p}, {p, y, p}, {p, y, -p}}, 1});
  }
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& q : t.p) scene.bounds.grow(q);
  scene.camera.position = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.yfov = 1.2f;  // tan(0.6) = 0.68 < 2: the view stays on the floor
  return scene;
}

// Direct light only (max depth 1: the eye vertex and its light sample), so the pane's mirror, which
// would send the floor's light back down, does not enter: every pixel reads kd/pi E cos(theta) times
// (1 - F(theta)) baseColor, with Schlick's F at the sun's angle -- exactly, since nothing in the
// estimate varies over the floor.
TEST(ThinGlassRender, ASunThroughAPaneLightsTheFloorByOneMinusFresnelTimesItsColour) {
  Scene open = floor_under_a_pane(false), glazed = floor_under_a_pane(true);
  ScenePunctualLight sun;
  sun.kind = ScenePunctualLight::Kind::directional;
  sun.direction = glm::vec3(float(std::sin(kTheta)), float(-std::cos(kTheta)), 0.0f);
  sun.intensity = kIrradiance;
  open.lights = glazed.lights = {sun};
  const ImageRGB a = render_pt(open, 16, 16, 4, 1, 1).image, b = render_pt(glazed, 16, 16, 4, 1, 1).image;
  const double fresnel = 0.04 + 0.96 * std::pow(1.0 - std::cos(kTheta), 5.0);  // Schlick, F0 0.04 at ior 1.5
  EXPECT_NEAR(pane_fresnel(kIor, float(std::cos(kTheta))), fresnel, 1e-6);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) {
        const double unobstructed = kAlbedo / M_PI * double(kIrradiance[c]) * std::cos(kTheta);
        ASSERT_NEAR(a.pixel(x, y)[c], unobstructed, 1e-3 * unobstructed) << "open, pixel " << x << "," << y;
        const double through = unobstructed * (1.0 - fresnel) * double(kTint[c]);
        ASSERT_NEAR(b.pixel(x, y)[c], through, 1e-3 * through) << "glazed, pixel " << x << "," << y << " channel " << c;
      }
}

// PT's walk through a pane: under a uniform sky L, without light sampling, one bounce (max depth 2),
// the floor reads kd L times the pane's transmittance averaged over the cosine-weighted hemisphere:
// baseColor (1 - F0) (1 - 1/21), since the integral of 2 mu (1 - mu)^5 over [0, 1] is 1/21. The
// pane's mirror sends the sky nowhere the floor sees at this depth. `pane_half_size` 100 m: the open
// band below the pane's edge (elevations under atan(1.5 / 98)) has a cosine-weighted share of
// 2.3e-4, which bounds how far the floor's mean may lie from the closed form beside the z-test.
TEST(ThinGlassRender, ThePathTracersWalkPassesAPaneAttenuatedByItsCosineWeightedFresnel) {
  const float sky = 1.5f;
  Scene glazed = floor_under_a_pane(true, 100.0f);
  glazed.environment = glm::vec3(sky);
  const int runs = 12;
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int k = 0; k < runs; ++k) {
    const ImageRGB img = render_pt(glazed, 16, 16, 64, 100 + 7 * k, 2, false).image;
    for (int c = 0; c < 3; ++c) {
      double m = 0.0;
      for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) m += img.pixel(x, y)[c] / 256.0;
      sum[c] += m;
      sum2[c] += m * m;
    }
  }
  const double f0 = pane_f0(kIor);
  const double band = std::pow(std::sin(std::atan(1.5 / 98.0)), 2.0);  // cos^2 of the band's top zenith angle
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / runs, se = std::sqrt((sum2[c] / runs - mean * mean) / (runs - 1));
    const double expected = kAlbedo * sky * double(kTint[c]) * (1.0 - f0) * (20.0 / 21.0);
    ASSERT_LT(se, 0.007 * expected) << "too few samples to see a 2 % error, channel " << c;
    EXPECT_LT(std::fabs(mean - expected), 4.0 * se + kAlbedo * sky * band)
        << "channel " << c << ": " << mean << " vs " << expected << " (se " << se << ")";
  }
}

CombinedRun combined(const Scene& scene, std::uint32_t seed, bool light_sampling, bool eye_shared,
                     std::uint64_t rounds = 64, std::uint32_t pt_samples_per_round = 1,
                     std::uint32_t rb_iterations_per_round = 4, std::uint32_t beta = BP_BETA_CLAMPED) {
  CombinedSettings cs;
  cs.weight_mode = BP_WEIGHTS_PRODUCT;
  cs.seed = seed;
  cs.rounds = rounds;  // 64 rounds: 64 spp + 256 iterations
  cs.pt_samples_per_round = pt_samples_per_round;
  cs.rb_iterations_per_round = rb_iterations_per_round;
  cs.beta_heuristic = beta;
  cs.patch_size = 0.05f;
  cs.light_sampling = light_sampling;
  cs.light_rate = 0.5f;
  cs.eye_direct_shared = eye_shared;
  return render_combined(scene, kSize, kSize, cs);
}

void expect_combination_agrees_with_pt(const Scene& scene, bool light_sampling, bool eye_shared, const char* what) {
  const int runs = 8;
  Sample reference = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 256, seed, 65536, light_sampling, BP_LIGHT_SELECTION_POWER).image;
  });
  Sample product = independent_runs(runs, [&](std::uint32_t seed) {
    return combined(scene, seed + 1, light_sampling, eye_shared).combined;
  });
  for (const std::string& d : significant_differences(product, reference, runs)) ADD_FAILURE() << what << ", " << d;
}

// The glossy light box with a tinted, partly opaque pane (T 0.7, ior 2: F0 1/9) across it below the
// light, seen from above the pane: the light reaches the room through it, the eye sees the room
// through it and the light and ceiling in its mirror (PT's alone).
Scene box_with_a_pane() {
  Scene scene = make_glossy_light_box();
  const std::uint32_t m = std::uint32_t(scene.materials.size());
  scene.materials.push_back(thin_pane(glm::vec3(0.9f, 0.8f, 0.6f), 0.7f, 2.0f, glm::vec3(0.15f)));
  const float y = 0.3f, h = 0.49f;
  scene.triangles.push_back({{{-h, y, -h}, {-h, y, h}, {h, y, h}}, m});
  scene.triangles.push_back({{{-h, y, -h}, {h, y, h}, {h, y, -h}}, m});
  scene.camera.position = glm::vec3(0.0f, 0.4f, 0.45f);
  scene.camera.forward = glm::normalize(glm::vec3(0.0f, -0.6f, -1.0f));
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  return scene;
}

TEST(ThinGlassRender, TheCombinationThroughAPaneAgreesWithThePathTracer) {
  const Scene scene = box_with_a_pane();
  expect_combination_agrees_with_pt(scene, false, false, "no light sampling");
  expect_combination_agrees_with_pt(scene, true, true, "light sampling, eye direct shared");
}

// The same box with the power to see a 2 % bias (power_test.h): a pane's transmittance
// missing on RB's side, or its mirror given to RB, moves the image by more than 2 %.
TEST(ThinGlassRender, TheCombinationThroughAPaneMatchesThePathTracerWithThePowerToSeeTwoPercent) {
  expect_combination_matches_pt_with_power_to_see_two_percent(box_with_a_pane(), "box with a pane");
}

// A sun through a glass ceiling (the glossy light box's ceiling made a clear pane, its lamp off): only
// the light samples reach the sun, PT's and RB's per-patch shadow rays, both through the pane, and
// the room's light leaves through it (RB's bundles, PT's walk) or comes back off its mirror (PT's).
TEST(ThinGlassRender, TheCombinationUnderASunThroughAGlassCeilingAgreesWithThePathTracer) {
  Scene scene = make_glossy_light_box();
  const std::uint32_t glass = std::uint32_t(scene.materials.size());
  scene.materials.push_back(thin_pane(glm::vec3(0.95f, 0.9f, 0.8f), 1.0f, 1.5f, glm::vec3(0.0f)));
  for (SceneTriangle& t : scene.triangles)
    if (t.p[0].y > 0.49f && t.p[1].y > 0.49f && t.p[2].y > 0.49f) t.material = t.material == 0 ? glass : t.material;
  std::erase_if(scene.triangles, [](const SceneTriangle& t) { return t.material == 2; });  // the lamp
  ScenePunctualLight sun;
  sun.kind = ScenePunctualLight::Kind::directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  sun.intensity = glm::vec3(2.0f, 1.8f, 1.5f);
  scene.lights.push_back(sun);
  expect_combination_agrees_with_pt(scene, true, false, "sun, eye direct PT's");
  // the eye vertex's direct light shared with RB on a Lambert floor, as Combination's sun test has it
  // (on the glossy floor RB's patch-level stand-in misses the sun's sharp highlight)
  scene.materials[1].kd = glm::vec3(0.6f);
  scene.materials[1].ks = glm::vec3(0.0f);
  expect_combination_agrees_with_pt(scene, true, true, "sun, Lambert floor, eye direct shared");
}

}  // namespace
}  // namespace bp::test

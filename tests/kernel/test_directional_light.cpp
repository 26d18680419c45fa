// Directional lights (KHR_lights_punctual "directional", docs/design.md §6): a delta in direction that only
// light sampling reaches. A grey plane under a sun at angle theta reads kd/pi E cos(theta) in every
// pixel -- exactly, since nothing in the estimate varies over the plane -- in the path tracer, and in
// each layer of the combination, whose split of a delta light is fixed (c/(c + 1) to RB's per-patch
// light samples, c = N2/N1 x rate, where the eye vertex's direct light is shared).
#include "kernel/device_fixture.h"
#include "kernel/region_test.h"
#include "device/device_scene.h"
#include "scene/lights.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

constexpr double kAlbedo = 0.6, kTheta = 0.9;  // radians from the plane's normal
const glm::vec3 kIrradiance(2.0f, 1.5f, 1.0f);  // W/m^2 of the sun, per colour

// A 4 m grey square at y = 0 facing +y, seen from 1 m above looking straight down (every pixel on
// it), under a sun kTheta from the zenith.
Scene plane_under_sun() {
  Scene scene;
  SceneMaterial grey;
  grey.kd = glm::vec3(float(kAlbedo));
  scene.materials = {grey};
  const float h = 2.0f;  // counter-clockwise seen from +y
  scene.triangles.push_back({{{-h, 0, -h}, {-h, 0, h}, {h, 0, h}}, 0});
  scene.triangles.push_back({{{-h, 0, -h}, {h, 0, h}, {h, 0, -h}}, 0});
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  ScenePunctualLight sun;
  sun.kind = ScenePunctualLight::Kind::directional;
  sun.direction = glm::vec3(float(std::sin(kTheta)), float(-std::cos(kTheta)), 0.0f);  // travelling down
  sun.intensity = kIrradiance;
  scene.lights = {sun};
  scene.camera.position = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.yfov = 1.2f;  // tan(0.6) = 0.68 < 2: the view stays on the plane
  return scene;
}

void expect_every_pixel(const ImageRGB& image, double share, const char* what) {
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double expected = share * kAlbedo / M_PI * double(kIrradiance[c]) * std::cos(kTheta);  // kd/pi E cos
        ASSERT_NEAR(image.pixel(x, y)[c], expected, 1e-3 * expected) << what << ", pixel " << x << "," << y;
      }
}

TEST(DirectionalLight, PlaneUnderASunReadsTheClosedFormInThePathTracer) {
  const Scene scene = plane_under_sun();
  for (std::uint32_t selection : {BP_LIGHT_SELECTION_TREE, BP_LIGHT_SELECTION_POWER})
    expect_every_pixel(render_pt(scene, 16, 16, 4, 1, 65536, true, selection).image, 1.0,
                       selection == BP_LIGHT_SELECTION_TREE ? "pt, tree" : "pt, power");
}

TEST(DirectionalLight, PlaneUnderASunReadsTheClosedFormInEachLayerOfTheCombination) {
  const Scene scene = plane_under_sun();
  for (float rate : {1.0f, 0.25f}) {
    CombinedSettings cs;
    cs.light_sampling = true;
    cs.eye_direct_shared = true;
    cs.light_rate = rate;
    cs.rounds = 8;
    cs.patch_size = 0.5f;
    const CombinedRun run = render_combined(scene, 16, 16, cs);
    const double c = 4.0 * rate, rb_share = c / (c + 1.0);  // N2/N1 = 4 iterations per sample
    expect_every_pixel(run.pt, 1.0 - rb_share, "pt layer");
    if (rate == 1.0f) expect_every_pixel(run.rb, rb_share, "rb layer");  // at rate 1 every patch samples: exact
    if (rate == 1.0f) expect_every_pixel(run.combined, 1.0, "combined");
  }
  // The eye vertex's direct light PT's alone: PT reads all of it.
  CombinedSettings cs;
  cs.light_sampling = true;
  cs.rounds = 4;
  cs.patch_size = 0.5f;
  expect_every_pixel(render_combined(scene, 16, 16, cs).pt, 1.0, "pt layer, --eye-direct pt");
}

// Outside the light tree (no position to bound), chosen with their share of the power: the
// probabilities of every light still sum to one for a receiver, and the sun's is its power share.
TEST(DirectionalLight, SelectionProbabilitiesSumToOneBesideTheTree) {
  Scene scene = plane_under_sun();
  ScenePunctualLight point;
  point.position = glm::vec3(0.5f, 0.5f, 0.2f);
  point.intensity = glm::vec3(0.3f);
  scene.lights.push_back(point);  // after the sun: the list puts directional lights last all the same
  SceneMaterial lamp;
  lamp.kd = glm::vec3(0.0f);
  lamp.emission = glm::vec3(3.0f);
  scene.materials.push_back(lamp);
  scene.triangles.push_back({{{-0.2f, 0.8f, -0.2f}, {0.2f, 0.8f, 0.2f}, {-0.2f, 0.8f, 0.2f}}, 1});  // facing down
  for (const glm::vec3& p : scene.triangles.back().p) scene.bounds.grow(p);
  LightList list = build_light_list(scene, build_bvh(scene.triangles));
  ASSERT_EQ(list.lights.size(), 3u);
  EXPECT_EQ(list.lights.back().type, BP_LIGHT_DIRECTIONAL);  // directional lights last
  const PatchLayout patches = build_patch_layout(scene, 0.5f);
  std::vector<LightTreeNode> tree = build_light_tree(list, scene, 1e-5f);
  std::vector<LightReceiver> receivers = build_light_receivers(scene, patches, list, 1e-5f);
  ASSERT_EQ(list.lights.back().type, BP_LIGHT_DIRECTIONAL);
  const LightSet set = light_set(list.lights.data(), list.cdf.data(), tree.data(), receivers.data(),
                                 std::uint32_t(list.lights.size()), BP_LIGHT_SELECTION_TREE);
  for (std::uint32_t patch = 0; patch < patches.patch_count; ++patch) {
    double sum = 0.0;
    for (std::uint32_t l = 0; l < list.lights.size(); ++l) sum += light_select_probability(&set, patch, l);
    EXPECT_NEAR(sum, 1.0, 1e-5) << "patch " << patch;
    EXPECT_FLOAT_EQ(light_select_probability(&set, patch, 2), list.lights[2].select_probability);
    // light_select draws what light_select_probability says
    for (float u : {0.0f, 0.3f, 0.7f, 0.99f}) {
      const LightPick pick = light_select(&set, patch, u);
      EXPECT_NEAR(pick.probability, light_select_probability(&set, patch, pick.light), 1e-6f) << "u " << u;
    }
  }
}

}  // namespace
}  // namespace bp::test

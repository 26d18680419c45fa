// Light sampling in the path tracer (docs/design.md §3, "Light sampling as a strategy"): point and spot
// lights against their closed-form direct light, and next-event estimation against the path tracer
// without it (per-region t-tests over independent runs).
#include "kernel/device_fixture.h"
#include "kernel/region_test.h"
#include "device/device_scene.h"
#include "kernels/shared/camera.h"

#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <functional>

namespace bp::test {
namespace {

constexpr float kHalf = 1.0f;     // the box is [-1, 1]^3
constexpr double kAlbedo = 0.6;   // of the floor; everything else is black

// A closed box with black walls and a grey Lambert floor, seen from just below the ceiling looking
// straight down: every pixel sees the floor, and the only light a floor point returns is direct.
Scene black_box_with_grey_floor() {
  SceneMaterial black;
  black.kd = glm::vec3(0.0f);
  Scene scene = make_closed_box(kHalf, black);
  SceneMaterial floor;
  floor.kd = glm::vec3(float(kAlbedo));
  scene.materials.push_back(floor);
  for (SceneTriangle& t : scene.triangles)
    if (t.p[0].y == -kHalf && t.p[1].y == -kHalf && t.p[2].y == -kHalf)
      t.material = std::uint32_t(scene.materials.size() - 1);
  scene.camera.position = glm::vec3(0.0f, 0.9f, 0.0f);
  scene.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.yfov = 0.8f;  // tan(0.4) * 1.9 = 0.8 < 1: the view stays on the floor
  return scene;
}

// Radiance the floor returns towards the camera through pixel (px, py) at jitter (jx, jy):
// rho / pi * I(direction) cos(theta) / d^2, the direct light of a point source.
using Intensity = std::function<double(const glm::dvec3& from_light)>;
double floor_radiance(const CameraParams& camera, const glm::dvec3& light, const Intensity& intensity, int px, int py,
                      double jx, double jy) {
  const float3 d = camera_ray_direction(&camera, std::uint32_t(px), std::uint32_t(py), float(jx), float(jy));
  const glm::dvec3 o(camera.position[0], camera.position[1], camera.position[2]), dir(d.x, d.y, d.z);
  const glm::dvec3 x = o + dir * ((-double(kHalf) - o.y) / dir.y);
  const glm::dvec3 to_light = light - x;
  const double dist2 = glm::dot(to_light, to_light), cos_theta = to_light.y / std::sqrt(dist2);
  return kAlbedo / M_PI * intensity(-glm::normalize(to_light)) * cos_theta / dist2;
}

// Each pixel of a path-traced render against the closed form averaged over the pixel (16x16
// sub-pixel grid). The estimator is noise-free apart from the pixel jitter, so the bound is the
// jitter's own: 5 standard errors of `spp` jittered samples of the closed form, plus float rounding.
void expect_direct_light(const Scene& scene, const glm::dvec3& light, const Intensity& intensity) {
  const int size = 24, spp = 64, grid = 16;
  RenderRun run = render_pt(scene, size, size, spp, 7);
  const CameraParams camera = pack_camera(scene.camera, size, size);
  double largest = 0.0;
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      double sum = 0.0, sum2 = 0.0;
      for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
          double l = floor_radiance(camera, light, intensity, px, py, (i + 0.5) / grid, (j + 0.5) / grid);
          sum += l;
          sum2 += l * l;
        }
      const double mean = sum / (grid * grid), sd = std::sqrt(std::max(0.0, sum2 / (grid * grid) - mean * mean));
      const double bound = 5.0 * sd / std::sqrt(double(spp)) + 1e-4 * mean + 1e-7;
      largest = std::max(largest, mean);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(run.image.pixel(px, py)[c], mean, bound) << "pixel " << px << "," << py << " channel " << c;
    }
  EXPECT_GT(largest, 0.01) << "the light did not reach the floor: the test would prove nothing";
}

TEST(LightSampling, PointLightGivesTheInverseSquareDirectLight) {
  Scene scene = black_box_with_grey_floor();
  ScenePunctualLight point;
  point.position = glm::vec3(0.3f, 0.5f, -0.2f);
  point.intensity = glm::vec3(2.0f);
  scene.lights.push_back(point);
  expect_direct_light(scene, glm::dvec3(point.position), [](const glm::dvec3&) { return 2.0; });
}

// KHR_lights_punctual's spot cone: t = clamp((cos - cos_outer) / (cos_inner - cos_outer), 0, 1),
// intensity I t^2 (the extension's recommended falloff), around the node's -z axis.
TEST(LightSampling, SpotLightFollowsTheGltfConeFalloff) {
  Scene scene = black_box_with_grey_floor();
  ScenePunctualLight spot;
  spot.kind = ScenePunctualLight::Kind::spot;
  spot.position = glm::vec3(0.1f, 0.2f, 0.0f);
  spot.direction = glm::vec3(0.0f, -1.0f, 0.0f);
  spot.intensity = glm::vec3(3.0f);
  spot.inner_cone = 0.2f;
  spot.outer_cone = 0.45f;
  scene.lights.push_back(spot);
  const double cos_inner = std::cos(0.2), cos_outer = std::cos(0.45);
  expect_direct_light(scene, glm::dvec3(spot.position), [&](const glm::dvec3& from_light) {
    const double t = std::clamp((-from_light.y - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0);
    return 3.0 * t * t;
  });
}

// Next-event estimation changes the noise, not the answer: on the glossy box (area light, glossy
// floor, grey walls: direct and indirect light, both techniques weighted by the balance heuristic)
// no 8x8 block, channel or image level differs significantly from the path tracer without it.
TEST(LightSampling, NextEventEstimationConvergesToThePathTracerWithoutIt) {
  Scene scene = make_glossy_light_box();
  const int runs = 8;
  Sample without = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 256, seed, 65536, false).image;
  });
  Sample with = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 64, seed + 100, 65536, true).image;
  });
  for (const std::string& d : significant_differences(with, without, runs)) ADD_FAILURE() << d;
  // And it pays: at a quarter of the samples, the block noise is lower.
  double se_with = 0.0, se_without = 0.0;
  for (int c = 0; c < kCells; ++c) {
    se_with += with.se[c];
    se_without += without.se[c];
  }
  EXPECT_LT(se_with, se_without);
}

// An area light and a point light together: the choice between them by power must weight each
// correctly, so the image equals the sum of the images of each light alone.
TEST(LightSampling, AreaAndPointLightsAddUp) {
  Scene area_only = make_glossy_light_box();
  Scene point_only = area_only;
  for (SceneMaterial& m : point_only.materials) m.emission = glm::vec3(0.0f);
  ScenePunctualLight point;
  point.position = glm::vec3(0.2f, 0.1f, 0.1f);
  point.intensity = glm::vec3(0.3f, 0.2f, 0.1f);
  point_only.lights.push_back(point);
  Scene both = area_only;
  both.lights.push_back(point);
  const int runs = 8;
  Sample sum = independent_runs(runs, [&](std::uint32_t seed) {
    ImageRGB a = render_pt(area_only, kSize, kSize, 32, seed).image;
    ImageRGB b = render_pt(point_only, kSize, kSize, 32, seed + 500).image;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] += b.rgb[i];
    return a;
  });
  Sample together = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(both, kSize, kSize, 64, seed + 900).image;
  });
  for (const std::string& d : significant_differences(together, sum, runs)) ADD_FAILURE() << d;
}

// Light selection by the light tree changes the noise, not the answer: under five lights of every
// kind (area one- and double-sided, point, spot; some behind a partition) no block, channel or
// image level differs significantly from selection by power.
TEST(LightSampling, TreeSelectionConvergesToPowerSelectionUnderManyLights) {
  Scene scene = make_multi_light_box();
  const int runs = 8;
  Sample power = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 64, seed, 65536, true, BP_LIGHT_SELECTION_POWER).image;
  });
  Sample tree = independent_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 64, seed + 100, 65536, true, BP_LIGHT_SELECTION_TREE).image;
  });
  for (const std::string& d : significant_differences(tree, power, runs)) ADD_FAILURE() << d;
  EXPECT_GT(tree.level, 0.01) << "the lights did not reach the image: the test would prove nothing";
}

}  // namespace
}  // namespace bp::test

// The first-hit albedo and normal a denoiser reads (passes/path_tracer.h, kernels/pathtrace.cl's
// first_hit_features; docs/design.md §13): a plain surface's albedo is its colour and its normal its
// own, exactly; glTF's model reads its Fresnel-weighted colour; through a pane, the albedo is what the
// pane passes on of the floor behind it plus what its mirror shows, in expectation.
#include "kernel/device_fixture.h"
#include "kernels/shared/thin_glass.h"
#include "passes/path_tracer.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

// A 4 m floor at y = 0 of `floor`, seen from 1 m above straight down through a narrow view (every
// ray within 0.3 degrees of the normal); `pane`: a pane of that material at y = 0.5 between.
Scene floor_seen_from_above(const SceneMaterial& floor, const SceneMaterial* pane = nullptr) {
  Scene scene;
  scene.materials = {floor};
  if (pane) scene.materials.push_back(*pane);
  const float h = 2.0f;
  scene.triangles.push_back({{{-h, 0, -h}, {-h, 0, h}, {h, 0, h}}, 0});
  scene.triangles.push_back({{{-h, 0, -h}, {h, 0, h}, {h, 0, -h}}, 0});
  if (pane) {
    scene.triangles.push_back({{{-h, 0.5f, -h}, {-h, 0.5f, h}, {h, 0.5f, h}}, 1});
    scene.triangles.push_back({{{-h, 0.5f, -h}, {h, 0.5f, h}, {h, 0.5f, -h}}, 1});
  }
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& q : t.p) scene.bounds.grow(q);
  scene.camera.position = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.yfov = 0.01f;
  return scene;
}

FirstHitFeatures features_of(const Scene& scene, int size = 16) {
  PatchLayout patches = build_patch_layout(scene, default_patch_size(scene));
  FlatBvh bvh = build_bvh(scene.triangles);
  DeviceScene device_scene(test_device(), scene, patches, bvh);
  return render_first_hit_features(test_device(), device_scene, pack_camera(scene.camera, size, size), "");
}

// Every pixel's albedo and normal, each channel against its expected value.
void expect_every_pixel(const FirstHitFeatures& f, const glm::vec3& albedo, const glm::vec3& normal, double tolerance) {
  for (std::size_t i = 0; i < f.albedo.rgb.size(); i += 3)
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(f.albedo.rgb[i + c], albedo[c], tolerance) << "pixel " << i / 3 << " channel " << c;
      ASSERT_NEAR(f.normal.rgb[i + c], normal[c], tolerance) << "pixel " << i / 3 << " channel " << c;
    }
}

TEST(FirstHitFeatures, ALambertFloorsAlbedoIsItsColourAndItsNormalItsOwn) {
  SceneMaterial lambert;
  lambert.kd = glm::vec3(0.7f, 0.4f, 0.1f);
  expect_every_pixel(features_of(floor_seen_from_above(lambert)), lambert.kd, glm::vec3(0, 1, 0), 1e-6);
}

TEST(FirstHitFeatures, GltfMaterialsReadTheirColourUnderTheFresnelLayer) {
  // Seen head-on, Schlick's weight is 0: a metal reflects its base colour; a dielectric its base under
  // a layer of f0 = 0.04, and the layer: (1 - 0.04) base + 0.04.
  SceneMaterial metal;
  metal.ggx = true;
  metal.base_color = glm::vec3(0.9f, 0.6f, 0.3f);
  metal.metallic = 1.0f;
  metal.roughness = 0.3f;
  expect_every_pixel(features_of(floor_seen_from_above(metal)), metal.base_color, glm::vec3(0, 1, 0), 2e-4);
  SceneMaterial plastic = metal;
  plastic.metallic = 0.0f;
  plastic.base_color = glm::vec3(0.5f, 0.2f, 0.0f);
  expect_every_pixel(features_of(floor_seen_from_above(plastic)), 0.96f * plastic.base_color + glm::vec3(0.04f),
                     glm::vec3(0, 1, 0), 2e-4);
}

TEST(FirstHitFeatures, ThroughAPaneTheAlbedoIsWhatItPassesOnPlusWhatItsMirrorShows) {
  // Each of the 16 rays of a pixel passes the pane with probability 1 - F and then reads the floor's
  // kd times the pane's (1 - F) tint over that probability, or takes the mirror (F) to the sky above
  // (albedo: its radiance, 0.5). The normal behind the pane is the floor's.
  SceneMaterial floor;
  floor.kd = glm::vec3(0.8f, 0.5f, 0.2f);
  SceneMaterial pane;
  pane.kd = glm::vec3(0.0f);
  pane.transmission = 1.0f;
  pane.transmission_tint = glm::vec3(0.9f, 0.6f, 0.3f);
  pane.ior = 1.5f;
  pane.double_sided = true;
  Scene scene = floor_seen_from_above(floor, &pane);
  scene.environment = glm::vec3(0.5f);
  const int size = 32;
  const FirstHitFeatures f = features_of(scene, size);
  const double fresnel = pane_fresnel(1.5f, 1.0f);
  // The event by albedo (thin_glass.h, pane_choice): pass by the mean of (1 - F) tint, mirror by F.
  const double pass_albedo = (1.0 - fresnel) * (pane.transmission_tint.x + pane.transmission_tint.y +
                                                pane.transmission_tint.z) / 3.0;
  const double p_pass = pass_albedo / (pass_albedo + fresnel), p_mirror = 1.0 - p_pass;
  const double samples = double(size) * size * 16;
  double normal_y = 0.0;
  for (std::size_t i = 0; i < f.normal.rgb.size(); i += 3) normal_y += f.normal.rgb[i + 1];
  normal_y /= double(size) * size;
  for (int c = 0; c < 3; ++c) {
    // A ray's albedo: the floor's kd times (1 - F) tint over p_pass where it passes; the sky's 0.5
    // times F over p_mirror where it mirrors.
    const double pass_value = floor.kd[c] * pane.transmission_tint[c] * (1.0 - fresnel) / p_pass;
    const double mirror_value = 0.5 * fresnel / p_mirror;
    const double expected = p_pass * pass_value + p_mirror * mirror_value;
    const double variance = p_pass * pass_value * pass_value + p_mirror * mirror_value * mirror_value -
                            expected * expected;
    double mean = 0.0;
    for (std::size_t i = 0; i < f.albedo.rgb.size(); i += 3) mean += f.albedo.rgb[i + c];
    mean /= double(size) * size;
    EXPECT_NEAR(mean, expected, 4.0 * std::sqrt(variance / samples) + 1e-6) << "channel " << c;  // + float rounding
  }
  // The mirror's rays see the sky (no normal), the others the floor's +y.
  EXPECT_NEAR(normal_y, p_pass, 4.0 * std::sqrt(p_pass * p_mirror / samples));
}

}  // namespace
}  // namespace bp::test

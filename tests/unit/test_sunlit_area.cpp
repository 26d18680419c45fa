// A directional light's selection power is its irradiance times the area, across its direction, of
// what it falls on first (sunlit_area, host/scene/lights.h): a room lit through a window gets the
// window's share of the light samples, not the share of the roof that the sun also crosses. The
// lattice of rays is off by at most one cell along each lit edge, which is the tolerance here.
#include "scene/lights.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

// Two triangles, counter-clockwise seen from the front: a, b, c, d around the quad.
void add_quad(Scene* scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, std::uint32_t material = 0) {
  scene->triangles.push_back({{a, b, c}, material});
  scene->triangles.push_back({{a, c, d}, material});
  for (const glm::vec3& p : {a, b, c, d}) scene->bounds.grow(p);
}

Scene with_grey_material(bool double_sided = false) {
  Scene scene;
  SceneMaterial grey;
  grey.kd = glm::vec3(0.5f);
  grey.double_sided = double_sided;
  scene.materials = {grey};
  return scene;
}

// The lattice's cell side for the scene, and the bound on its error for a lit region of this perimeter.
double tolerance(const Scene& scene, double perimeter) {
  const double cell = glm::length(scene.bounds.extent()) / kSunlitGrid;
  return perimeter * cell;
}

// A 4 m square facing +y under a sun 0.9 rad from the zenith: its area times cos(0.9); from below
// (the sun on its back) nothing.
TEST(SunlitArea, PlaneFacingTheSunCountsItsProjectedArea) {
  Scene scene = with_grey_material();
  add_quad(&scene, {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2});
  const FlatBvh bvh = build_bvh(scene.triangles);
  const double theta = 0.9;
  const glm::vec3 down(float(std::sin(theta)), float(-std::cos(theta)), 0.0f);
  const double expected = 16.0 * std::cos(theta);
  EXPECT_NEAR(sunlit_area(scene, bvh, down, kSunlitGrid), expected,
              tolerance(scene, 2.0 * (4.0 + 4.0 * std::cos(theta))));
  EXPECT_EQ(sunlit_area(scene, bvh, -down, kSunlitGrid), 0.0);
}

// A closed 4 m box whose one-sided walls face inwards, with a 1 m window in its roof, under a sun a
// little off the zenith: the sun falls on the floor through the window alone (the roof's outside is
// its back), 1 m^2 times cos(theta) across the light. Double-sided, the box is lit wherever the sun
// meets it: its outline across the light, 16 m^2 times |d.x| + |d.y| + |d.z|.
Scene box_with_window(bool double_sided) {
  Scene scene = with_grey_material(double_sided);
  const float h = 2.0f, w = 0.5f;
  add_quad(&scene, {-h, -h, -h}, {-h, -h, h}, {h, -h, h}, {h, -h, -h});  // floor, facing +y
  add_quad(&scene, {-h, -h, -h}, {h, -h, -h}, {h, h, -h}, {-h, h, -h});  // back, facing +z
  add_quad(&scene, {-h, -h, h}, {-h, h, h}, {h, h, h}, {h, -h, h});      // front, facing -z
  add_quad(&scene, {-h, -h, -h}, {-h, h, -h}, {-h, h, h}, {-h, -h, h});  // left, facing +x
  add_quad(&scene, {h, -h, -h}, {h, -h, h}, {h, h, h}, {h, h, -h});      // right, facing -x
  // the roof at y = h, facing -y, in four pieces around the window |x|, |z| < w
  add_quad(&scene, {-h, h, -h}, {h, h, -h}, {h, h, -w}, {-h, h, -w});
  add_quad(&scene, {-h, h, w}, {h, h, w}, {h, h, h}, {-h, h, h});
  add_quad(&scene, {-h, h, -w}, {-w, h, -w}, {-w, h, w}, {-h, h, w});
  add_quad(&scene, {w, h, -w}, {h, h, -w}, {h, h, w}, {w, h, w});
  return scene;
}

TEST(SunlitArea, RoomLitThroughAWindowCountsTheWindow) {
  const glm::vec3 down = glm::normalize(glm::vec3(0.05f, -1.0f, 0.03f));
  const double cos_down = -double(down.y);
  const Scene room = box_with_window(false);
  EXPECT_NEAR(sunlit_area(room, build_bvh(room.triangles), down, kSunlitGrid), 1.0 * cos_down, tolerance(room, 4.0));
  const Scene outside = box_with_window(true);
  const double outline = 16.0 * (std::abs(down.x) + std::abs(down.y) + std::abs(down.z));
  EXPECT_NEAR(sunlit_area(outside, build_bvh(outside.triangles), down, kSunlitGrid), outline, tolerance(outside, 24.0));
}

// The light list gives the sun E times that area against an area light's pi Le A, and a sun that
// nothing faces keeps a positive share (one lattice cell's), so no light is ever left unsampled.
TEST(SunlitArea, SetsTheSunsShareOfTheLightSamples) {
  Scene room = box_with_window(false);
  SceneMaterial lamp;
  lamp.emission = glm::vec3(2.0f);
  room.materials.push_back(lamp);
  // 0.8 m square, facing -y, off the window's shaft
  add_quad(&room, {1.0f, 1.9f, -0.4f}, {1.8f, 1.9f, -0.4f}, {1.8f, 1.9f, 0.4f}, {1.0f, 1.9f, 0.4f}, 1);
  ScenePunctualLight sun;
  sun.kind = ScenePunctualLight::Kind::directional;
  sun.direction = glm::normalize(glm::vec3(0.05f, -1.0f, 0.03f));
  sun.intensity = glm::vec3(3.0f);
  room.lights = {sun};
  const FlatBvh bvh = build_bvh(room.triangles);
  const LightList list = build_light_list(room, bvh);
  ASSERT_EQ(list.lights.back().type, BP_LIGHT_DIRECTIONAL);
  const double sun_power = 3.0 * sunlit_area(room, bvh, sun.direction, kSunlitGrid), lamp_power = M_PI * 2.0 * 0.64;
  EXPECT_NEAR(list.lights.back().select_probability, sun_power / (sun_power + lamp_power), 1e-6);
  EXPECT_LT(list.lights.back().select_probability, 0.5);  // the whole disk would have given it 0.97

  room.lights[0].direction = -sun.direction;  // from below: the floor's back, the walls' backs
  const LightList dark = build_light_list(room, build_bvh(room.triangles));
  EXPECT_GT(dark.lights.back().select_probability, 0.0f);
  EXPECT_LT(dark.lights.back().select_probability, 1e-3f);
}

}  // namespace
}  // namespace bp::test

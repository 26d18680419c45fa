// A directional light's selection power is its irradiance times the area, across its direction, of
// what it falls on first (sunlit_area, host/scene/lights.h): a room lit through a window gets the
// window's share of the light samples, not the share of the roof that the sun also crosses. The
// lattice of rays is off by at most one cell along each lit edge, which is the tolerance here.
// Per receiving patch, the share shrinks where the sun (or the sky) does not reach it
// (LightReceiver.infinite_visibility, build_light_receivers).
#include "scene/light_tree.h"
#include "scene/lights.h"
#include "kernels/shared/lights.h"

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


// The room with a roof window and a lamp beside the shaft (SetsTheSunsShareOfTheLightSamples), its
// patches' receivers built with the BVH.
struct LitRoom {
  Scene scene;
  FlatBvh bvh;
  PatchLayout patches;
  LightList list;
  std::vector<LightTreeNode> tree;
  std::vector<LightReceiver> receivers;
  LightSet set() const {
    return light_set(list.lights.data(), list.cdf.data(), tree.data(), receivers.data(),
                     std::uint32_t(list.lights.size()), BP_LIGHT_SELECTION_TREE);
  }
};

LitRoom lit_room(glm::vec3 sun_direction, glm::vec3 environment, bool roof = true) {
  LitRoom r;
  r.scene = box_with_window(false);
  if (!roof) std::erase_if(r.scene.triangles, [](const SceneTriangle& t) { return t.p[0].y == 2.0f && t.p[1].y == 2.0f && t.p[2].y == 2.0f; });
  SceneMaterial lamp;
  lamp.emission = glm::vec3(2.0f);
  r.scene.materials.push_back(lamp);
  add_quad(&r.scene, {1.0f, 1.9f, -0.4f}, {1.8f, 1.9f, -0.4f}, {1.8f, 1.9f, 0.4f}, {1.0f, 1.9f, 0.4f}, 1);
  if (glm::length(sun_direction) > 0.0f) {
    ScenePunctualLight sun;
    sun.kind = ScenePunctualLight::Kind::directional;
    sun.direction = sun_direction;
    sun.intensity = glm::vec3(3.0f);
    r.scene.lights = {sun};
  }
  r.scene.environment = environment;
  r.bvh = build_bvh(r.scene.triangles);
  r.patches = build_patch_layout(r.scene, 0.25f);
  r.list = build_light_list(r.scene, r.bvh);
  r.tree = build_light_tree(r.list, r.scene, 1e-4f);
  r.receivers = build_light_receivers(r.scene, r.patches, r.list, 1e-4f, &r.bvh);
  return r;
}

// A sun straight down through the 1 m window: floor patches inside its square see it from every
// point (visibility 1), floor patches well outside it and walls (edge-on) from none (the floor,
// 1 / kVisibilityRays). Per receiver the probabilities still sum to one and light_select draws what
// they say; the sun's is the light list's share where it is seen, and far less where it is not.
TEST(InfiniteVisibility, ScalesTheSunsShareByWhatEachPatchSeesOfIt) {
  const LitRoom room = lit_room(glm::vec3(0.0f, -1.0f, 0.0f), glm::vec3(0.0f));
  const LightSet set = room.set();
  const std::uint32_t sun = std::uint32_t(room.list.lights.size() - 1);
  ASSERT_EQ(room.list.lights[sun].type, BP_LIGHT_DIRECTIONAL);
  const float share = room.list.lights[sun].select_probability;
  int lit = 0, dark = 0;
  for (std::uint32_t p = 0; p < room.patches.patch_count; ++p) {
    const LightReceiver& rec = room.receivers[p];
    const glm::vec3 c(rec.centroid[0], rec.centroid[1], rec.centroid[2]), n(rec.normal[0], rec.normal[1], rec.normal[2]);
    const bool floor = n.y > 0.99f, inside = std::max(std::abs(c.x), std::abs(c.z)) + rec.radius < 0.5f,
               outside = std::max(std::abs(c.x), std::abs(c.z)) - rec.radius > 0.5f;
    const float p_sun = light_select_probability(&set, p, sun);
    if (floor && inside) {
      ++lit;
      EXPECT_FLOAT_EQ(rec.infinite_visibility, 1.0f) << "patch " << p;
      EXPECT_NEAR(p_sun, share, 1e-6f) << "patch " << p;
    }
    if ((floor && outside) || std::abs(n.y) < 0.01f) {
      ++dark;
      EXPECT_FLOAT_EQ(rec.infinite_visibility, 1.0f / kVisibilityRays) << "patch " << p;
      const float odds = share / kVisibilityRays;
      EXPECT_NEAR(p_sun, odds / (odds + 1.0f - share), 1e-6f) << "patch " << p;
    }
    double sum = 0.0;
    for (std::uint32_t l = 0; l < room.list.lights.size(); ++l) sum += light_select_probability(&set, p, l);
    EXPECT_NEAR(sum, 1.0, 1e-5) << "patch " << p;
    for (float u : {0.0f, 0.01f, share * 0.5f, 0.3f, 0.7f, 0.99f}) {
      const LightPick pick = light_select(&set, p, u);
      EXPECT_NEAR(pick.probability, light_select_probability(&set, p, pick.light), 1e-6f) << "patch " << p;
    }
  }
  EXPECT_GT(lit, 0);
  EXPECT_GT(dark, lit);
}

// A uniform sky over the room without its roof: the floor's middle sees much of it, the floor's
// corners less, nothing less than 1 / kVisibilityRays; with the roof, its 1 m window is about 2 % of
// the cosine-weighted sky from the floor, which 16 rays miss: every patch gets the floor.
TEST(InfiniteVisibility, EnvironmentCountsTheSkyEachPatchSees) {
  for (bool roof : {false, true}) {
    const LitRoom room = lit_room(glm::vec3(0.0f), glm::vec3(1.0f), roof);
    ASSERT_EQ(room.list.lights.back().type, BP_LIGHT_ENVIRONMENT);
    float middle = 0.0f, corner = 1.0f;
    for (std::uint32_t p = 0; p < room.patches.patch_count; ++p) {
      const LightReceiver& rec = room.receivers[p];
      EXPECT_GE(rec.infinite_visibility, 1.0f / kVisibilityRays);
      EXPECT_LE(rec.infinite_visibility, 1.0f);
      const glm::vec3 c(rec.centroid[0], rec.centroid[1], rec.centroid[2]);
      if (rec.normal[1] < 0.99f) continue;
      if (std::max(std::abs(c.x), std::abs(c.z)) < 0.3f) middle = std::max(middle, rec.infinite_visibility);
      if (std::min(std::abs(c.x), std::abs(c.z)) > 1.6f) corner = std::min(corner, rec.infinite_visibility);
    }
    if (roof) {
      EXPECT_FLOAT_EQ(middle, 1.0f / kVisibilityRays);
    } else {  // a 4 m square opening 4 m above: its view factor from the middle is 0.24 (four 2 m x 2 m
              // rectangles' corner factors); 16 stratified rays are within 0.1 of it
      EXPECT_NEAR(middle, 0.24f, 0.1f);
      EXPECT_LT(corner, middle);
    }
  }
}

}  // namespace
}  // namespace bp::test

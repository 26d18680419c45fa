// The shipped scenes (scenes/*.gltf, written by scripts/make_cornell_scenes.py).
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bp {
namespace {

using test::scene_file;

const SceneMaterial* find_material(const Scene& s, const std::string& name) {
  for (const auto& m : s.materials)
    if (m.name == name) return &m;
  return nullptr;
}

glm::vec3 centroid(const SceneTriangle& t) { return (t.p[0] + t.p[1] + t.p[2]) / 3.0f; }

void expect_cornell_frame(const Scene& s) {
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // Bounds: the published box in metres.
  EXPECT_NEAR(s.bounds.lo.x, 0.0f, 1e-6);
  EXPECT_NEAR(s.bounds.lo.y, 0.0f, 1e-6);
  EXPECT_NEAR(s.bounds.lo.z, 0.0f, 1e-6);
  EXPECT_NEAR(s.bounds.hi.x, 0.556f, 1e-6);
  EXPECT_NEAR(s.bounds.hi.y, 0.5488f, 1e-6);
  EXPECT_NEAR(s.bounds.hi.z, 0.5592f, 1e-6);
  // Camera: (0.278, 0.273, -0.8) looking along +z, up +y, 35 mm lens on 25 mm film.
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_NEAR(s.camera.position.x, 0.278f, 1e-6);
  EXPECT_NEAR(s.camera.position.y, 0.273f, 1e-6);
  EXPECT_NEAR(s.camera.position.z, -0.8f, 1e-6);
  EXPECT_NEAR(s.camera.forward.z, 1.0f, 1e-6);
  EXPECT_NEAR(s.camera.up.y, 1.0f, 1e-6);
  EXPECT_NEAR(s.camera.yfov, 2.0f * std::atan(12.5f / 35.0f), 1e-6);
  EXPECT_FLOAT_EQ(s.camera.aspect, 1.0f);

  const SceneMaterial* light = find_material(s, "light");
  ASSERT_NE(light, nullptr);
  EXPECT_NEAR(light->emission.x, 17.0f, 1e-5);
  EXPECT_NEAR(light->emission.y, 12.0f, 1e-5);
  EXPECT_NEAR(light->emission.z, 4.0f, 1e-5);
  EXPECT_EQ(light->kd, glm::vec3(0.0f));
  EXPECT_FALSE(light->double_sided);
  EXPECT_EQ(s.emissive_triangles(), 2u);

  // The camera's right is forward x up; the red wall must lie to its left, the green to its right.
  const glm::vec3 right = glm::cross(s.camera.forward, s.camera.up);
  const SceneMaterial* red = find_material(s, "red");
  const SceneMaterial* green = find_material(s, "green");
  ASSERT_NE(red, nullptr);
  ASSERT_NE(green, nullptr);
  int red_seen = 0, green_seen = 0;
  const glm::vec3 inside = s.bounds.centre();
  for (const auto& t : s.triangles) {
    const SceneMaterial& m = s.materials[t.material];
    const float side = glm::dot(centroid(t) - s.camera.position, right);
    if (&m == red) {
      EXPECT_LT(side, 0.0f);
      ++red_seen;
    }
    if (&m == green) {
      EXPECT_GT(side, 0.0f);
      ++green_seen;
    }
    if (&m == light) {
      EXPECT_LT(test::normal_of(t).y, 0.0f) << "the light faces down";
    }
    // Walls, floor and ceiling face the box's inside.
    const glm::vec3 n = test::normal_of(t);
    const glm::vec3 c = centroid(t);
    const bool wall = c.x < 1e-3f || c.x > 0.549f || c.y < 1e-3f || c.y > 0.5487f || c.z > 0.559f;
    if (wall && &m != light) {
      EXPECT_GT(glm::dot(n, inside - c), 0.0f);
    }
  }
  EXPECT_EQ(red_seen, 2);
  EXPECT_EQ(green_seen, 2);
}

TEST(CornellScene, BoxLoadsWithPublishedGeometryAndMaterials) {
  const Scene s = load_gltf(scene_file("cornell-box.gltf"));
  EXPECT_EQ(s.triangles.size(), 32u);  // 5 walls + light + 2 blocks x 5 faces, 2 triangles each
  expect_cornell_frame(s);
  const SceneMaterial* white = find_material(s, "white");
  ASSERT_NE(white, nullptr);
  EXPECT_NEAR(white->kd.x, 0.725f, 1e-6);
  EXPECT_NEAR(white->kd.y, 0.71f, 1e-6);
  EXPECT_NEAR(white->kd.z, 0.68f, 1e-6);
  EXPECT_EQ(white->ks, glm::vec3(0.0f));
  const SceneMaterial* red = find_material(s, "red");
  EXPECT_NEAR(red->kd.x, 0.63f, 1e-6);
  EXPECT_NEAR(red->kd.y, 0.065f, 1e-6);
  const SceneMaterial* green = find_material(s, "green");
  EXPECT_NEAR(green->kd.y, 0.45f, 1e-6);
  EXPECT_NEAR(green->kd.z, 0.091f, 1e-6);
}

TEST(CornellScene, GlossyVariantHasPaperMaterialsAndAnEgg) {
  const Scene s = load_gltf(scene_file("cornell-glossy.gltf"));
  expect_cornell_frame(s);
  const SceneMaterial* glossy = find_material(s, "glossy white");
  const SceneMaterial* block = find_material(s, "block");
  const SceneMaterial* egg = find_material(s, "egg");
  ASSERT_TRUE(glossy && block && egg);
  EXPECT_EQ(glossy->ks, glm::vec3(0.85f));
  EXPECT_FLOAT_EQ(glossy->shininess, 50.0f);
  EXPECT_NEAR(glossy->kd.x, 0.15f, 1e-6);
  EXPECT_EQ(block->kd, glm::vec3(0.5f));
  EXPECT_EQ(block->ks, glm::vec3(0.5f));
  EXPECT_FLOAT_EQ(block->shininess, 10.0f);
  EXPECT_EQ(egg->kd, glm::vec3(0.1f));
  EXPECT_EQ(egg->ks, glm::vec3(0.8f));
  EXPECT_FLOAT_EQ(egg->shininess, 10.0f);
  for (const auto& m : s.materials)
    for (int c = 0; c < 3; ++c) EXPECT_LE(m.kd[c] + m.ks[c], 1.0f) << m.name;

  // The egg: 1-2k triangles, outward normals, standing on the floor, clear of the blocks.
  Bounds egg_bounds;
  std::size_t egg_triangles = 0;
  for (const auto& t : s.triangles)
    if (&s.materials[t.material] == egg) {
      ++egg_triangles;
      for (const auto& p : t.p) egg_bounds.grow(p);
    }
  EXPECT_GE(egg_triangles, 1000u);
  EXPECT_LE(egg_triangles, 2000u);
  EXPECT_EQ(s.triangles.size(), 32u + egg_triangles);
  EXPECT_NEAR(egg_bounds.lo.y, 0.0f, 1e-3);
  EXPECT_GT(egg_bounds.extent().y, 1.2f * egg_bounds.extent().x);
  const glm::vec3 centre = egg_bounds.centre();
  for (const auto& t : s.triangles)
    if (&s.materials[t.material] == egg) {
      EXPECT_GT(glm::dot(test::normal_of(t), centroid(t) - centre), 0.0f);
    }
  EXPECT_GT(egg_bounds.lo.x, 0.29f);   // right of the short block (x <= 0.29)
  EXPECT_LT(egg_bounds.hi.z, 0.247f);  // in front of the tall block (z >= 0.247)
  EXPECT_LT(egg_bounds.hi.x, 0.549f);  // inside the red wall
}

TEST(CornellScene, NormalMapVariantHasABumpyBackWall) {
  const Scene s = load_gltf(scene_file("cornell-normal-map.gltf"));
  EXPECT_EQ(s.triangles.size(), 32u);
  expect_cornell_frame(s);
  const SceneMaterial* bumpy = find_material(s, "bumpy white");
  ASSERT_NE(bumpy, nullptr);
  ASSERT_TRUE(bumpy->has_normal_map());
  EXPECT_EQ(s.texture_views[bumpy->textures.normal].width, 64u);
  // no NORMAL, no TANGENT: flat normals (-z, into the box) and generated tangents along u (-x), w +1
  int walls = 0;
  for (const auto& t : s.triangles)
    if (&s.materials[t.material] == bumpy) {
      ++walls;
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(t.normal[k].z, -1.0f, 1e-6f);
        EXPECT_NEAR(t.tangent[k].x, -1.0f, 1e-4f);
        EXPECT_EQ(t.tangent[k].w, 1.0f);
      }
    }
  EXPECT_EQ(walls, 2);
}

// The glass variant: the Lambert box with a solid glass egg, read as a refractor with its medium.
TEST(CornellScene, GlassVariantHasASolidGlassEgg) {
  const Scene s = load_gltf(scene_file("cornell-glass.gltf"));
  expect_cornell_frame(s);
  const SceneMaterial* glass = find_material(s, "glass");
  ASSERT_NE(glass, nullptr);
  EXPECT_TRUE(glass->volume);
  EXPECT_FLOAT_EQ(glass->transmission, 1.0f);
  EXPECT_FLOAT_EQ(glass->ior, 1.5f);
  EXPECT_NEAR(glass->attenuation.x, -std::log(0.8f) / 0.2f, 1e-4f);  // 80 % of red left after 0.2 m
  EXPECT_TRUE(s.has_transmission());
  std::size_t egg = 0;
  for (const auto& t : s.triangles) egg += &s.materials[t.material] == glass;
  EXPECT_EQ(s.triangles.size(), 32u + egg);
  EXPECT_GE(egg, 1000u);
}

}  // namespace
}  // namespace bp

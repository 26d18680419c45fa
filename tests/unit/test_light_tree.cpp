// The light tree of light selection (kernels/shared/light_tree.h, host/scene/light_tree.cpp) on the
// host: probabilities that sum to one for every receiver, sampling frequencies that match them, and
// an importance that is never zero for a light that some point of the patch could see from its front.
#include "stats.h"

#include "kernels/shared/lights.h"
#include "kernels/shared/patch.h"
#include "scene/gltf_loader.h"
#include "scene/light_tree.h"
#include "scene/lights.h"
#include "scene/patches.h"
#include "scene/procedural.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include <string>

namespace bp::test {
namespace {

// Everything light selection reads, built as DeviceScene builds it.
struct TreeRig {
  Scene scene;
  PatchLayout patches;
  LightList list;
  std::vector<LightTreeNode> nodes;
  std::vector<LightReceiver> receivers;

  TreeRig(Scene s, float patch_size) : scene(std::move(s)) {
    patches = build_patch_layout(scene, patch_size);
    list = build_light_list(scene, build_bvh(scene.triangles));
    nodes = build_light_tree(list, scene, 1e-5f);
    receivers = build_light_receivers(scene, patches, list, 1e-5f);
  }
  LightSet set(std::uint32_t selection = BP_LIGHT_SELECTION_TREE) const {
    return light_set(list.lights.data(), list.cdf.data(), nodes.data(), receivers.data(),
                     std::uint32_t(list.lights.size()), selection);
  }
};

double probability_sum(const LightSet& set, std::uint32_t patch, bool* finite) {
  double sum = 0.0;
  for (std::uint32_t l = 0; l < set.count; ++l) {
    const float p = light_select_probability(&set, patch, l);
    if (!std::isfinite(p) || p < 0.0f) *finite = false;
    sum += p;
  }
  return sum;
}

// Sum over lights of P(light | patch) = 1 for random patches of the scene, and for made-up receivers
// anywhere in and around it (inside the lights, of no size, of huge size, any normal).
void expect_probabilities_sum_to_one(const TreeRig& rig) {
  ASSERT_FALSE(rig.list.lights.empty());
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::uint32_t> patch(0, rig.patches.patch_count - 1);
  const LightSet set = rig.set();
  for (int i = 0; i < 400; ++i) {
    const std::uint32_t p = patch(rng);
    bool finite = true;
    EXPECT_NEAR(probability_sum(set, p, &finite), 1.0, 1e-5) << "patch " << p;
    EXPECT_TRUE(finite) << "patch " << p;
  }
  std::vector<LightReceiver> made_up(1);
  LightSet any = set;
  any.receivers = made_up.data();
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const glm::vec3 lo = rig.scene.bounds.lo, extent = rig.scene.bounds.extent();
  for (int i = 0; i < 400; ++i) {
    LightReceiver& r = made_up[0];
    glm::vec3 c = lo + extent * glm::vec3(unit(rng) * 1.4f - 0.2f, unit(rng) * 1.4f - 0.2f, unit(rng) * 1.4f - 0.2f);
    if (i % 10 == 0) {  // on a light's vertex
      const Light& l = rig.list.lights[i % rig.list.lights.size()];
      c = glm::vec3(l.position[0], l.position[1], l.position[2]);
    }
    glm::vec3 n = glm::normalize(glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f) + 1e-6f);
    const float radii[4] = {0.0f, 1e-4f, 0.1f, 1e3f};
    for (int k = 0; k < 3; ++k) {
      r.centroid[k] = c[k];
      r.normal[k] = n[k];
    }
    r.radius = radii[i % 4] * glm::length(extent);
    bool finite = true;
    EXPECT_NEAR(probability_sum(any, 0, &finite), 1.0, 1e-5) << "made-up receiver " << i;
    EXPECT_TRUE(finite) << "made-up receiver " << i;
  }
}

TEST(LightTree, ProbabilitiesSumToOneForEveryReceiverInTheRooms) {
  TreeRig rig(make_rooms_scene(100000, 1), 0.5f);
  EXPECT_GE(rig.list.lights.size(), 40u);  // 25 rooms, one two-triangle panel each
  expect_probabilities_sum_to_one(rig);
}

TEST(LightTree, ProbabilitiesSumToOneForEveryReceiverInTheCornellBoxes) {
  for (const char* name : {"cornell-box.gltf", "cornell-glossy.gltf"}) {
    SCOPED_TRACE(name);
    Scene s = load_gltf(std::string(BP_SOURCE_DIR) + "/scenes/" + name);
    TreeRig rig(std::move(s), 0.05f);
    expect_probabilities_sum_to_one(rig);
  }
}

// A room's own ceiling panel is the likeliest choice for its floor: the point of the tree.
TEST(LightTree, TheRoomsOwnLightIsChosenFarMoreOftenThanByPower) {
  TreeRig rig(make_rooms_scene(100000, 1), 0.5f);
  const LightSet set = rig.set();
  // The receiver under the camera's room: a floor patch near the camera (y close to the floor, facing up).
  const glm::vec3 eye = rig.scene.camera.position;
  std::uint32_t best = 0;
  float best_d = INFINITY;
  for (std::uint32_t p = 0; p < rig.patches.patch_count; ++p) {
    const LightReceiver& r = rig.receivers[p];
    if (r.normal[1] < 0.99f) continue;
    const float dx = r.centroid[0] - eye.x, dz = r.centroid[2] - eye.z, dy = r.centroid[1] - (eye.y - 1.6f);
    const float d = dx * dx + dy * dy + dz * dz;
    if (d < best_d) {
      best_d = d;
      best = p;
    }
  }
  double nearest_two = 0.0, power_two = 0.0;
  std::vector<std::pair<float, std::uint32_t>> by_distance;
  for (std::uint32_t l = 0; l < set.count; ++l) {
    const Light& light = rig.list.lights[l];
    const glm::vec3 c(rig.receivers[best].centroid[0], rig.receivers[best].centroid[1], rig.receivers[best].centroid[2]);
    by_distance.push_back({glm::length(glm::vec3(light.position[0], light.position[1], light.position[2]) - c), l});
  }
  std::sort(by_distance.begin(), by_distance.end());
  for (int k = 0; k < 2; ++k) {  // the panel's two triangles
    nearest_two += light_select_probability(&set, best, by_distance[k].second);
    power_two += rig.list.lights[by_distance[k].second].select_probability;
  }
  EXPECT_GT(nearest_two, 5.0 * power_two) << "tree " << nearest_two << ", power " << power_two;
}

// light_tree_select draws each light as often as light_select_probability says (chi-square, pooled
// cells, Šidák over the receivers), and reports that same probability with the pick.
TEST(LightTree, SamplingFrequenciesMatchTheSelectionProbabilities) {
  TreeRig rig(make_rooms_scene(100000, 3), 0.5f);
  const LightSet set = rig.set();
  const int receivers = 12, draws = 200000;
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::uint32_t> patch(0, rig.patches.patch_count - 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < receivers; ++i) {
    const std::uint32_t p = patch(rng);
    std::vector<double> observed(set.count, 0.0), expected(set.count, 0.0);
    for (std::uint32_t l = 0; l < set.count; ++l) expected[l] = draws * double(light_select_probability(&set, p, l));
    for (int d = 0; d < draws; ++d) {
      const LightPick pick = light_select(&set, p, std::min(unit(rng), 0.99999994f));
      ASSERT_LT(pick.light, set.count);
      observed[pick.light] += 1.0;
      ASSERT_EQ(pick.probability, light_select_probability(&set, p, pick.light));  // bit for bit
    }
    const ChiSquareResult r = chi_square_test(observed, expected);
    EXPECT_GT(r.p_value, sidak_alpha(0.01, receivers)) << "patch " << p << ": chi2 " << r.statistic << ", dof " << r.dof;
  }
}

// The density that weights an emitter reached otherwise (PT's BSDF hit, RB's bundle) is the one the
// light sample carried: P(select) / area from the emitter's patch, bit for bit, for both selections.
TEST(LightTree, TheEmitterHitDensityIsTheLightSamplesDensity) {
  TreeRig rig(make_rooms_scene(20000, 4), 0.5f);
  std::vector<Material> materials(rig.scene.materials.size());
  for (std::size_t m = 0; m < materials.size(); ++m) materials[m].light_pdf_area = rig.list.material_pdf_area[m];
  std::mt19937 rng(2);
  std::uniform_int_distribution<std::uint32_t> patch(0, rig.patches.patch_count - 1);
  std::uniform_real_distribution<float> unit(0.0f, 0.99999994f);
  for (std::uint32_t selection : {BP_LIGHT_SELECTION_TREE, BP_LIGHT_SELECTION_POWER}) {
    const LightSet set = rig.set(selection);
    for (int i = 0; i < 2000; ++i) {
      const std::uint32_t receiver = patch(rng);
      const LightPick pick = light_select(&set, receiver, unit(rng));
      const Light& l = rig.list.lights[pick.light];
      std::uint32_t t = 0;
      while (rig.list.light_of_triangle[t] != pick.light) ++t;
      const std::uint32_t emitter_patch = rig.patches.first_patch[t];
      const float pdf_area = light_pdf_area_from(&set, materials.data(), receiver, emitter_patch, l.material);
      if (selection == BP_LIGHT_SELECTION_TREE) EXPECT_EQ(pdf_area, pick.probability / l.area);
      else EXPECT_NEAR(pdf_area, pick.probability / l.area, 1e-5 * pdf_area);  // one number per material
    }
  }
}

// A scene to try to break the culling: receivers of every size and orientation, small triangle
// lights (one- and double-sided) of every orientation close to them, point and spot lights.
Scene light_cloud(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto point = [&](float lo, float hi) {
    return glm::vec3(lo + (hi - lo) * unit(rng), lo + (hi - lo) * unit(rng), lo + (hi - lo) * unit(rng));
  };
  Scene s;
  SceneMaterial grey, one_sided, two_sided;
  one_sided.emission = glm::vec3(3.0f);
  two_sided.emission = glm::vec3(1.0f);
  two_sided.double_sided = true;
  grey.double_sided = true;  // both sides receive
  s.materials = {grey, one_sided, two_sided};
  for (int i = 0; i < 12; ++i) {  // receivers, 0.05 to 2 m
    const glm::vec3 a = point(0.0f, 1.0f);
    const float size = 0.05f * std::pow(40.0f, unit(rng));
    s.triangles.push_back({{a, a + point(-1.0f, 1.0f) * size, a + point(-1.0f, 1.0f) * size}, 0});
  }
  for (int i = 0; i < 60; ++i) {  // lights, 1 cm to 10 cm
    const glm::vec3 a = point(-0.2f, 1.2f);
    const float size = 0.01f * std::pow(10.0f, unit(rng));
    s.triangles.push_back({{a, a + point(-1.0f, 1.0f) * size, a + point(-1.0f, 1.0f) * size}, i % 4 == 0 ? 2u : 1u});
  }
  for (int i = 0; i < 8; ++i) {
    ScenePunctualLight l;
    l.position = point(-0.2f, 1.2f);
    if (i % 2) {
      l.kind = ScenePunctualLight::Kind::spot;
      l.direction = glm::normalize(point(-1.0f, 1.0f));
      l.inner_cone = 0.1f * unit(rng);
      l.outer_cone = 0.2f + 1.2f * unit(rng);
    }
    s.lights.push_back(l);
  }
  for (const SceneTriangle& t : s.triangles)
    for (const glm::vec3& p : t.p) s.bounds.grow(p);
  return s;
}

// Whether a light point y (normal ny for a triangle) lights x from x's front (normal nx), as light
// sampling tests it.
bool lights_point(const Light& l, bool double_sided, const glm::dvec3& y, const glm::dvec3& x, const glm::dvec3& nx) {
  const glm::dvec3 d = x - y;
  if (!(glm::dot(nx, -d) > 0.0)) return false;
  const glm::dvec3 axis(l.axis[0], l.axis[1], l.axis[2]);
  if (l.type == BP_LIGHT_TRIANGLE) return double_sided ? glm::dot(axis, d) != 0.0 : glm::dot(axis, d) > 0.0;
  if (l.type == BP_LIGHT_SPOT) return glm::dot(axis, glm::normalize(d)) > double(l.cos_outer);
  return true;
}

// Every light that some point of a patch could see from its front has a selection probability
// above zero for that patch (else the estimate would be biased); and the tree does cull (the test
// is not vacuous): lights behind a patch get zero.
TEST(LightTree, ImportanceIsNeverZeroForALightThatAnyPointOfThePatchCanSee) {
  int culled = 0, checked_visible = 0;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    TreeRig rig(light_cloud(seed), 10.0f);  // patches as large as their triangles: the hard case
    const LightSet set = rig.set();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::size_t t = 0; t < rig.scene.triangles.size(); ++t) {
      const SceneTriangle& tri = rig.scene.triangles[t];
      if (tri.material != 0) continue;
      const std::uint32_t k = rig.patches.subdiv[t];
      for (std::uint32_t side = 0; side < 2; ++side)
        for (std::uint32_t local = 0; local < k * k; ++local) {
          const std::uint32_t patch = rig.patches.first_patch[t] + side * k * k + local;
          float b1[3], b2[3];
          patch_corner_barycentrics(local, k, b1, b2);
          glm::dvec3 c[3];
          for (int i = 0; i < 3; ++i)
            c[i] = glm::dvec3(tri.p[0]) + double(b1[i]) * glm::dvec3(tri.p[1] - tri.p[0]) +
                   double(b2[i]) * glm::dvec3(tri.p[2] - tri.p[0]);
          const glm::dvec3 nx(rig.receivers[patch].normal[0], rig.receivers[patch].normal[1],
                              rig.receivers[patch].normal[2]);
          for (std::uint32_t l = 0; l < set.count; ++l) {
            const Light& light = rig.list.lights[l];
            const bool two = light.type == BP_LIGHT_TRIANGLE && rig.scene.materials[light.material].double_sided;
            const glm::dvec3 y0(light.position[0], light.position[1], light.position[2]);
            const glm::dvec3 e1(light.edge1[0], light.edge1[1], light.edge1[2]), e2(light.edge2[0], light.edge2[1], light.edge2[2]);
            bool visible = false;
            for (int s = 0; s < 400 && !visible; ++s) {
              // patch corners and edges first (the extremes), then its interior; light corners likewise
              double u = unit(rng), v = unit(rng);
              if (s < 9) { u = (s % 3) * 0.5; v = (s / 3) * 0.5; }
              if (u + v > 1.0) { u = 1.0 - u; v = 1.0 - v; }
              const glm::dvec3 x = c[0] + u * (c[1] - c[0]) + v * (c[2] - c[0]);
              double a = unit(rng), b = unit(rng);
              if (s % 4 == 0) { a = (s / 4) % 3 == 1; b = (s / 4) % 3 == 2; }
              if (a + b > 1.0) { a = 1.0 - a; b = 1.0 - b; }
              const glm::dvec3 y = light.type == BP_LIGHT_TRIANGLE ? y0 + a * e1 + b * e2 : y0;
              visible = lights_point(light, two, y, x, nx);
            }
            const float p = light_select_probability(&set, patch, l);
            if (visible) {
              ++checked_visible;
              EXPECT_GT(p, 0.0f) << "seed " << seed << ", patch " << patch << ", light " << l;
            } else if (p == 0.0f) {
              ++culled;
            }
          }
        }
    }
  }
  EXPECT_GT(checked_visible, 1000);
  EXPECT_GT(culled, 100) << "the tree never culled: the test proves nothing";
}

// A light right at the corner of a large patch, just above it and facing it, or grazing it from
// beside: small but not zero. Behind the patch, or the patch behind the light: zero.
TEST(LightTree, ALightAtTheCornerOfALargePatchIsNeverCulled) {
  Scene s;
  SceneMaterial floor, light;
  light.emission = glm::vec3(5.0f);
  s.materials = {floor, light};
  s.triangles.push_back({{{0, 0, 0}, {10, 0, 0}, {0, 0, -10}}, 0});  // facing +y, 10 m
  auto add_light = [&](glm::vec3 at, bool face_down) {
    const float e = 0.01f;
    if (face_down) s.triangles.push_back({{at, at + glm::vec3(0, 0, -e), at + glm::vec3(e, 0, 0)}, 1});
    else s.triangles.push_back({{at, at + glm::vec3(e, 0, 0), at + glm::vec3(0, 0, -e)}, 1});
  };
  add_light({10.0f, 0.001f, 0.0f}, true);      // 1 mm above the far corner, facing down
  add_light({10.05f, 0.0005f, 0.001f}, true);  // beside the corner, barely above the plane
  add_light({10.0f, 0.001f, 0.0f}, false);     // above the corner but facing up: cannot light it
  add_light({5.0f, -0.5f, -5.0f}, false);      // under the floor, facing up: behind the floor
  for (const SceneTriangle& t : s.triangles)
    for (const glm::vec3& p : t.p) s.bounds.grow(p);
  TreeRig rig(std::move(s), 100.0f);
  ASSERT_EQ(rig.patches.subdiv[0], 1u);
  const LightSet set = rig.set();
  auto p = [&](std::uint32_t triangle) { return light_select_probability(&set, 0, rig.list.light_of_triangle[triangle]); };
  EXPECT_GT(p(1), 0.0f);
  EXPECT_GT(p(2), 0.0f);
  EXPECT_EQ(p(3), 0.0f);
  EXPECT_EQ(p(4), 0.0f);
}

// One light: a single leaf, chosen with probability exactly 1 without any importance evaluated.
TEST(LightTree, OneLightIsOneLeafChosenWithProbabilityOne) {
  Scene s;
  SceneMaterial floor, light;
  light.emission = glm::vec3(5.0f);
  s.materials = {floor, light};
  s.triangles.push_back({{{0, 0, 0}, {1, 0, 0}, {0, 0, -1}}, 0});
  s.triangles.push_back({{{0, 1, 0}, {0, 1, -1}, {1, 1, 0}}, 1});
  for (const SceneTriangle& t : s.triangles)
    for (const glm::vec3& p : t.p) s.bounds.grow(p);
  TreeRig rig(std::move(s), 0.3f);
  ASSERT_EQ(rig.nodes.size(), 1u);
  EXPECT_EQ(rig.list.lights[0].tree_depth, 0u);
  const LightSet set = rig.set();
  const LightPick pick = light_select(&set, 0, 0.7f);
  EXPECT_EQ(pick.light, 0u);
  EXPECT_EQ(pick.probability, 1.0f);
}

// The Cornell boxes' light is one panel (two triangles): the tree is a single leaf, chosen without
// any importance evaluated, and its triangles by power as without the tree.
TEST(LightTree, OnePanelIsOneLeafAndItsTrianglesAreChosenByPower) {
  for (const char* name : {"cornell-box.gltf", "cornell-glossy.gltf"}) {
    SCOPED_TRACE(name);
    TreeRig rig(load_gltf(std::string(BP_SOURCE_DIR) + "/scenes/" + name), 0.05f);
    ASSERT_EQ(rig.nodes.size(), 1u);
    EXPECT_EQ(rig.nodes[0].leaf_lights, rig.list.lights.size());
    const LightSet tree = rig.set(), power = rig.set(BP_LIGHT_SELECTION_POWER);
    for (std::uint32_t l = 0; l < tree.count; ++l)
      EXPECT_NEAR(light_select_probability(&tree, 5, l), light_select_probability(&power, 5, l), 1e-6);
  }
}

// Power selection is what it was: the cdf and each light's power share, whatever the receiver.
TEST(LightTree, PowerSelectionIgnoresTheReceiver) {
  TreeRig rig(make_rooms_scene(20000, 2), 0.5f);
  const LightSet set = rig.set(BP_LIGHT_SELECTION_POWER);
  for (std::uint32_t p : {0u, 17u, rig.patches.patch_count - 1})
    for (std::uint32_t l = 0; l < set.count; ++l)
      EXPECT_EQ(light_select_probability(&set, p, l), rig.list.lights[l].select_probability);
  const LightPick pick = light_select(&set, 3, 0.5f);
  EXPECT_EQ(pick.light, light_pick(rig.list.cdf.data(), set.count, 0.5f));
}

// Many lights in one spot (a dense emissive mesh): the tree stays within its 64 trail bits.
TEST(LightTree, DepthStaysWithinTheTrailBitsForManyLights) {
  Scene s;
  SceneMaterial light;
  light.emission = glm::vec3(1.0f);
  s.materials = {SceneMaterial{}, light};
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 20000; ++i) {
    // exponentially clustered: a naive SAH would build a very deep spine
    const float x = std::pow(2.0f, -40.0f * unit(rng));
    s.triangles.push_back({{{x, 0, 0}, {x + 1e-7f, 0, 0}, {x, 1e-7f, 0}}, 1});
  }
  for (const SceneTriangle& t : s.triangles)
    for (const glm::vec3& p : t.p) s.bounds.grow(p);
  LightList list = build_light_list(s, build_bvh(s.triangles));
  std::vector<LightTreeNode> nodes = build_light_tree(list, s, 1e-6f);
  std::uint32_t deepest = 0;
  for (const Light& l : list.lights) deepest = std::max(deepest, l.tree_depth);
  EXPECT_LE(deepest, 64u);
  // Each light's trail leads to the leaf that holds it.
  for (std::uint32_t i = 0; i < list.lights.size(); i += 97) {
    const Light& l = list.lights[i];
    std::uint32_t node = 0;
    for (std::uint32_t k = 0; k < l.tree_depth; ++k) {
      const bool second = ((k < 32 ? l.tree_trail[0] >> k : l.tree_trail[1] >> (k - 32)) & 1u) != 0;
      ASSERT_FALSE(nodes[node].flags & BP_LIGHT_NODE_LEAF);
      node = second ? nodes[node].child : node + 1;
    }
    ASSERT_TRUE(nodes[node].flags & BP_LIGHT_NODE_LEAF);
    EXPECT_LE(nodes[node].child, i);
    EXPECT_LT(i, nodes[node].child + nodes[node].leaf_lights);
  }
}

}  // namespace
}  // namespace bp::test

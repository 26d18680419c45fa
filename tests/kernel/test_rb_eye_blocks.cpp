// The eye estimate in blocks (RayBundleSettings::eye_blocks, docs/design.md §8): Lambert eye vertices
// gathered once per block of iterations from per-patch sums give the same image as the gather of
// every iteration -- the same sums in another order, so equal to float rounding -- in every
// configuration the eye estimate has: each weight mode, light sampling with the eye's direct light
// shared, the raw layer, Gouraud and flat, Phong patches beside Lambert ones (gathered every
// iteration), an all-Lambert scene (rb_eye not launched at all) and the environment.
#include "kernel/device_fixture.h"

#include "device/kernel_features.h"

#include <gtest/gtest.h>
#include <atomic>
#include <cmath>
#include <string>

namespace bp::test {
namespace {

struct Config {
  std::string name;
  Scene scene;
  RayBundleSettings settings;
};

// The accumulator after `iterations` eye estimates (the render loop's batches: 1, 2, 4, ..., so
// blocks end both at the eye hits' refresh every 16 iterations and at the batches' flushes).
Accumulator render(const Config& c, bool eye_blocks, std::uint64_t iterations) {
  const int width = 24, height = 20;
  Scene scene = c.scene;
  const PatchLayout patches = build_patch_layout(scene, 0.1f);
  const FlatBvh bvh = build_bvh(scene.triangles);
  const BundleGeometry geometry = build_bundle_geometry(scene, patches);
  DeviceScene device_scene(test_device(), scene, patches, bvh);
  RayBundleSettings settings = c.settings;
  settings.eye_blocks = eye_blocks;
  settings.glossy = features_for(scene, settings.light_sampling).glossy();
  Accumulator accum(width, height, settings.keep_raw);
  RayBundlePass pass(test_device(), device_scene, geometry, pack_camera(scene.camera, width, height), settings, accum);
  std::atomic<bool> never{false};
  run_progressive(pass, RenderBudget{iterations, 0.0}, never, nullptr);
  return accum;
}

void expect_same_sums(const std::vector<double>& blocks, const std::vector<double>& every, const std::string& what) {
  ASSERT_EQ(blocks.size(), every.size()) << what;
  double total = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < every.size(); ++i) {
    total += every[i];
    // float sums of at most 64 terms in another order: a few ulps of the larger terms
    worst = std::max(worst, std::fabs(blocks[i] - every[i]) / (std::fabs(every[i]) + 1e-3));
  }
  EXPECT_GT(total, 0.0) << what;
  EXPECT_LT(worst, 2e-5) << what;
}

TEST(RayBundleEyeBlocks, EqualEveryIterationsGatherInEveryConfiguration) {
  std::vector<Config> configs;
  SceneMaterial lambert;
  lambert.kd = glm::vec3(0.6f, 0.5f, 0.4f);
  lambert.emission = glm::vec3(0.3f);
  Scene furnace = make_closed_box(1.0f, lambert);  // every eye vertex Lambert: rb_eye is not launched
  {
    Config c{"furnace, no weights", furnace, {}};
    configs.push_back(c);
    c.name = "furnace, product weights, balance beta";
    c.settings.weight_mode = BP_WEIGHTS_PRODUCT;
    c.settings.weight_ratio = 0.25f;
    c.settings.beta_heuristic = BP_BETA_BALANCE;
    c.settings.keep_raw = true;
    configs.push_back(c);
  }
  RayBundleSettings product;
  product.weight_mode = BP_WEIGHTS_PRODUCT;
  product.weight_ratio = 0.125f;
  product.light_sampling = true;
  product.eye_direct_shared = true;
  product.keep_raw = true;
  configs.push_back({"glossy box, product weights, light sampling, eye direct shared, raw", make_glossy_light_box(),
                     product});
  RayBundleSettings flat = product;
  flat.gouraud = false;
  configs.push_back({"multi-light box, flat", make_multi_light_box(), flat});
  RayBundleSettings eye_direct_pt = product;
  eye_direct_pt.eye_direct_shared = false;
  eye_direct_pt.keep_raw = false;
  configs.push_back({"multi-light box, eye direct PT's", make_multi_light_box(), eye_direct_pt});
  RayBundleSettings paper;
  paper.weight_mode = BP_WEIGHTS_PAPER;
  configs.push_back({"glossy box, paper weights (every iteration)", make_glossy_light_box(), paper});
  Scene open_box = make_glossy_light_box();  // the environment through the missing back wall, in view
  std::erase_if(open_box.triangles, [](const SceneTriangle& t) {
    return t.p[0].z == -0.5f && t.p[1].z == -0.5f && t.p[2].z == -0.5f;
  });
  open_box.environment = glm::vec3(0.2f, 0.3f, 0.5f);
  configs.push_back({"glossy box under a uniform environment", open_box, product});

  for (const Config& c : configs) {
    const Accumulator blocks = render(c, true, 40), every = render(c, false, 40);
    expect_same_sums(blocks.sum, every.sum, c.name);
    if (c.settings.keep_raw) expect_same_sums(blocks.raw_sum, every.raw_sum, c.name + " (raw)");
  }
}

}  // namespace
}  // namespace bp::test

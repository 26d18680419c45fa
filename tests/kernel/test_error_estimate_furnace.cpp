// The error estimate (docs/design.md §9) on the path tracer in the furnace, whose per-sample variance is
// known: closed box, every surface emitting Le, Lambert albedo a, no light sampling; with s = a the
// throughput stays 1, so a sample is Le times a geometric count of vertices, variance Le² a/(1−a)².
#include "kernel/device_fixture.h"
#include "image/error_estimate.h"
#include "passes/path_tracer.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

void expect_furnace_variance(float albedo, float le, int size, std::uint64_t spp) {
  SceneMaterial m;
  m.kd = glm::vec3(albedo);
  m.emission = glm::vec3(le);
  Scene scene = make_closed_box(1.0f, m);
  const DeviceContext& device = test_device();
  PatchLayout patches = build_patch_layout(scene, default_patch_size(scene));
  FlatBvh bvh = build_bvh(scene.triangles);
  DeviceScene device_scene(device, scene, patches, bvh);
  PathTracerSettings settings;
  settings.seed = 4;
  settings.light_sampling = false;
  Accumulator accum(size, size);
  PathTracerPass pass(device, device_scene, pack_camera(scene.camera, size, size), settings, accum);
  BatchMeansErrorEstimate estimate(size, size, 1);
  const RoundSums sums{&accum.sum};
  std::atomic<bool> never{false};
  run_progressive(pass, RenderBudget{spp, 0.0, {}}, never,
                  [&](const RenderProgress& p) { estimate.add(p.rounds_done, sums); });
  ASSERT_GE(estimate.batches(), 8u);
  const double sample_variance = double(le) * le * albedo / ((1.0 - albedo) * (1.0 - albedo));
  const std::vector<double> var = estimate.variance_of_mean();
  // The three channels are one grey walk: channel R of each pixel is one independent value.
  const std::size_t pixels = std::size_t(size) * size;
  double sum = 0.0, sum_sq = 0.0;
  for (std::size_t i = 0; i < pixels; ++i) {
    const double ratio = var[i * 3] * double(spp) / sample_variance;  // 1 in expectation
    sum += ratio;
    sum_sq += ratio * ratio;
  }
  const double mean = sum / double(pixels);
  const double se = std::sqrt((sum_sq / double(pixels) - mean * mean) / double(pixels - 1));
  // Two furnaces here: Šidák at alpha = 0.01; the standard error from the pixels' own spread.
  EXPECT_LT(std::fabs(mean - 1.0) / se, z_for_two_sided(sidak_alpha(0.01, 2)))
      << "albedo " << albedo << ": estimated / known variance " << mean << " ± " << se;
  EXPECT_LT(se, 0.03) << "the test must be sharp enough to see a 10 % error";
  // And the relMSE the estimate reports is that variance over (I² + 0.01), I = Le / (1 − a).
  const double image = le / (1.0 - albedo);
  EXPECT_NEAR(estimate.estimated_rel_mse(sums), sample_variance / double(spp) / (image * image + 0.01),
              5.0 * se * sample_variance / double(spp) / (image * image + 0.01));
}

TEST(ErrorEstimateFurnace, HalfAlbedo) { expect_furnace_variance(0.5f, 1.0f, 48, 512); }
TEST(ErrorEstimateFurnace, HighAlbedo) { expect_furnace_variance(0.8f, 0.5f, 48, 256); }

}  // namespace
}  // namespace bp::test

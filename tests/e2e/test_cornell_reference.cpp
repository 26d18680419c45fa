// `--mode pt` on the Cornell box against an independent reference renderer (tests/e2e/
// reference_renderer.*, which shares no sampling, BRDF, RNG or BVH code with the kernels):
// the mean level agrees within 2 %, and no region differs beyond its statistical error.
#include "e2e/reference_renderer.h"
#include "kernel/device_fixture.h"
#include "scene/gltf_loader.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

TEST(CornellReference, PathTracerAgreesWithIndependentRenderer) {
  Scene scene = load_gltf(std::string(BP_SOURCE_DIR) + "/scenes/cornell-box.gltf");
  const int w = 32, h = 32, block = 4, runs = 24;
  const std::uint64_t spp_per_run = 24;

  // Ours: independent runs (seeds), so each block's standard error comes from their spread.
  const int bw = w / block, bh = h / block, cells = bw * bh * 3;
  std::vector<std::vector<double>> block_means(runs, std::vector<double>(cells, 0.0));
  double our_total = 0.0;
  for (int k = 0; k < runs; ++k) {
    RenderRun run = render_pt(scene, w, h, spp_per_run, 1000u + k);
    ASSERT_EQ(run.outcome.nonfinite_samples, 0u);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          double v = run.image.pixel(x, y)[c];
          block_means[k][((y / block) * bw + x / block) * 3 + c] += v / (block * block);
          our_total += v;
        }
  }
  ReferenceResult ref = render_reference(scene, w, h, 512, 7u);
  double ref_total = 0.0;
  std::vector<double> ref_block(cells, 0.0), ref_var(cells, 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        int cell = ((y / block) * bw + x / block) * 3 + c;
        ref_block[cell] += ref.mean.pixel(x, y)[c] / (block * block);
        double se = ref.std_error.pixel(x, y)[c] / (block * block);
        ref_var[cell] += se * se;
        ref_total += ref.mean.pixel(x, y)[c];
      }

  // Mean level within 2 %.
  double our_mean = our_total / runs;
  EXPECT_NEAR(our_mean / ref_total, 1.0, 0.02) << "ours " << our_mean << " reference " << ref_total;

  // Per block and channel: Welch-style t on the difference, Šidák-corrected over all cells.
  const double alpha = sidak_alpha(0.01, cells);
  int failures = 0;
  for (int cell = 0; cell < cells; ++cell) {
    double m = 0.0, s2 = 0.0;
    for (int k = 0; k < runs; ++k) m += block_means[k][cell] / runs;
    for (int k = 0; k < runs; ++k) s2 += (block_means[k][cell] - m) * (block_means[k][cell] - m) / (runs - 1);
    double se = std::sqrt(s2 / runs + ref_var[cell]);
    if (se == 0.0) {  // nothing reaches this region in either renderer
      EXPECT_NEAR(m, ref_block[cell], 1e-6);
      continue;
    }
    double t = (m - ref_block[cell]) / se;
    double p = student_t_two_sided_p(t, runs - 1);
    if (p < alpha) {
      ++failures;
      ADD_FAILURE() << "block (" << (cell / 3) % bw << ", " << (cell / 3) / bw << ") channel " << cell % 3
                    << ": ours " << m << " reference " << ref_block[cell] << " (t = " << t << ")";
    }
  }
  EXPECT_EQ(failures, 0);
}

}  // namespace
}  // namespace bp::test

// The path tracer on the test device: the furnace (analytic), determinism, NaN guards.
#include "kernel/device_fixture.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

// Closed box, every surface emitting Le with Lambert albedo a: every pixel is Le / (1 - a).
// With s = a the throughput stays 1, so one sample is Le times the number of vertices the walk
// visits, geometric with mean 1/(1-a) and variance a/(1-a)^2: the tolerance follows from that.
void expect_furnace(float albedo, float le, int width, int height, std::uint64_t spp) {
  SceneMaterial m;
  m.kd = glm::vec3(albedo);
  m.emission = glm::vec3(le);
  Scene scene = make_closed_box(1.0f, m);
  RenderRun run = render_pt(scene, width, height, spp, 3u);
  const double expected = le / (1.0 - albedo);
  const double sample_sd = le * std::sqrt(albedo) / (1.0 - albedo);
  double n = double(width) * height * double(spp);
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (int i = 0; i < width * height; ++i) sum += run.image.rgb[std::size_t(i) * 3 + c];
    double mean = sum / (width * height);
    if (sample_sd == 0.0) {  // albedo 0: every sample is exactly Le
      EXPECT_NEAR(mean, expected, 1e-6 * expected) << "channel " << c;
      continue;
    }
    double z = (mean - expected) / (sample_sd / std::sqrt(n));
    // 3 channels x 3 furnaces in this file: Šidák at alpha = 0.01.
    EXPECT_LT(std::fabs(z), z_for_two_sided(sidak_alpha(0.01, 9)))
        << "albedo " << albedo << " channel " << c << ": mean " << mean << " expected " << expected;
  }
  EXPECT_EQ(run.outcome.nonfinite_samples, 0u);
}

TEST(PathTraceFurnace, HalfAlbedo) { expect_furnace(0.5f, 1.0f, 32, 32, 64); }
TEST(PathTraceFurnace, HighAlbedo) { expect_furnace(0.9f, 0.25f, 24, 24, 64); }
TEST(PathTraceFurnace, BlackWallsEmitOnly) { expect_furnace(0.0f, 2.0f, 16, 16, 4); }

TEST(PathTraceDeterminism, SameSeedIsBitIdenticalOtherSeedDiffers) {
  SceneMaterial m;
  m.kd = glm::vec3(0.7f, 0.5f, 0.3f);
  m.ks = glm::vec3(0.2f);
  m.shininess = 20.0f;
  m.emission = glm::vec3(0.5f);
  Scene scene = make_closed_box(1.0f, m);
  RenderRun a = render_pt(scene, 24, 16, 9, 42u);
  RenderRun b = render_pt(scene, 24, 16, 9, 42u);
  RenderRun c = render_pt(scene, 24, 16, 9, 43u);
  EXPECT_EQ(a.image.rgb, b.image.rgb);
  EXPECT_EQ(a.outcome.rays, b.outcome.rays);
  EXPECT_NE(a.image.rgb, c.image.rgb);
}

TEST(PathTraceCounters, RaysCountWhatWasTraced) {
  // Black, non-reflecting walls: every path is one camera ray that hits a wall and stops.
  SceneMaterial m;
  m.kd = glm::vec3(0.0f);
  m.emission = glm::vec3(1.0f);
  Scene scene = make_closed_box(1.0f, m);
  RenderRun run = render_pt(scene, 10, 10, 3, 1u);
  EXPECT_EQ(run.outcome.rays, 10u * 10u * 3u);
  EXPECT_EQ(run.outcome.rounds, 3u);
}

}  // namespace
}  // namespace bp::test

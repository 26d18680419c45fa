// Global ray-bundle iteration on the test device against analytic results (docs/design.md §4).
#include "kernel/device_fixture.h"
#include "stats.h"

#include <gtest/gtest.h>
#include <cmath>
#include <numeric>

namespace bp::test {
namespace {

// Per iteration: the power the receiver (material 1 of make_parallel_squares) got, sum_p A_p E_in,p
// (channel 0), minus the control variate C = Le A |cos theta_omega| -- what an infinite emitter
// would give -- whose mean over directions uniform on the sphere is exactly Le A / 2.
std::vector<double> received_minus_control(BundleRig& rig, int iterations, double le, double receiver_area) {
  std::vector<double> out;
  for (int t = 0; t < iterations; ++t) {
    rig.pass->iterate(std::uint64_t(t));
    std::vector<cl_float4> e_in = rig.pass->read_patch_irradiance();
    double sum = 0.0;
    for (const BundleElement& el : rig.geometry.elements)
      if (el.material == 1) sum += double(el.area) * e_in[el.front_patch].s[0];
    const double cos_omega = std::fabs(rig.pass->iteration_params(std::uint64_t(t)).omega[2]);
    out.push_back(sum - le * receiver_area * cos_omega);
  }
  return out;
}

// One bounce between two parallel unit squares: in expectation sum_p A_p E_in,p = Le A F / 2
// (E_in estimates L cos(theta) for a direction uniform over the receiver's hemisphere, so its mean is
// the irradiance over 2 pi, and the power is Le pi A F). The receiver is black, so iterations are
// independent and the standard error is the sample's.
void expect_form_factor(float patch_size, std::uint32_t bins, int iterations, const char* what) {
  const double le = 1.0, side = 1.0, distance = 0.2, area = side * side;
  auto rig = make_bundle_rig(make_parallel_squares(float(side), float(distance), float(le)), patch_size, bins, 5u);
  std::vector<double> residual = received_minus_control(*rig, iterations, le, area);
  double mean = std::accumulate(residual.begin(), residual.end(), 0.0) / iterations, var = 0.0;
  for (double r : residual) var += (r - mean) * (r - mean) / (iterations - 1);
  const double estimate = mean + le * area / 2.0;
  const double expected = le * area * parallel_rectangles_form_factor(side, side, distance) / 2.0;
  const double standard_error = std::sqrt(var / iterations);
  const double z = (estimate - expected) / standard_error;
  EXPECT_LT(std::fabs(z), z_for_two_sided(sidak_alpha(0.01, 3)))
      << what << ": estimate " << estimate << " expected " << expected << " (standard error " << standard_error << ")";
  // The test must be able to see a 2 % error in the transfer.
  EXPECT_LT(standard_error / expected, 0.004) << what;
}

TEST(RayBundleAnalytic, FormFactorOfParallelSquares) {
  EXPECT_NEAR(parallel_rectangles_form_factor(1, 1, 1), 0.19982, 1e-4);  // the catalogue's value
  expect_form_factor(0.25f, 96, 3000, "patches a few bins wide");
}

TEST(RayBundleAnalytic, PatchesFarSmallerThanABinGetTheRightExpectation) {
  expect_form_factor(0.06f, 4, 8000, "patches 1/6 of a bin");
}

TEST(RayBundleAnalytic, OnePatchFarLargerThanABinGetsTheRightExpectation) {
  expect_form_factor(10.0f, 256, 2500, "one patch per triangle");
}

// A closed box with a cube inside: every bin's fragments pair up, so per iteration the power
// received, sum_p A_p E_in,p, equals the power sent, sum_p L_out,p n_bins(p) A_bin -- exactly where
// touching surfaces exchange radiance too (contact depth 0); with the contact rule (the box's corner
// edges and the cube on the floor touch) to within the touching fragments' share.
void expect_closed_scene_power_balance(float contact_depth_fraction, double tolerance) {
  SceneMaterial m;
  m.kd = glm::vec3(0.6f, 0.4f, 0.2f);
  m.emission = glm::vec3(0.3f, 0.5f, 0.7f);
  Scene scene = make_closed_box(1.0f, m);
  Scene inner = make_closed_box(0.3f, m);
  for (SceneTriangle t : inner.triangles) {
    std::swap(t.p[1], t.p[2]);  // outward-facing cube
    scene.triangles.push_back(t);
  }
  auto rig = make_bundle_rig(scene, 0.2f, 80, 9u, 8, 8, 0, kStaticTiledBytes, contact_depth_fraction);
  const double bin_area = std::pow(2.0 * rig->geometry.radius / rig->pass->bins(), 2.0);
  for (int t = 0; t < 20; ++t) {
    rig->pass->iterate(std::uint64_t(t));
    std::vector<cl_float4> e_in = rig->pass->read_patch_irradiance(), l_out = rig->pass->read_patch_outgoing();
    std::vector<cl_uint> counts = rig->pass->read_fragment_counts();
    for (int c = 0; c < 3; ++c) {
      double received = 0.0, sent = 0.0;
      for (std::size_t e = 0; e < rig->geometry.elements.size(); ++e) {
        const BundleElement& el = rig->geometry.elements[e];
        received += double(el.area) * e_in[el.front_patch].s[c];
        sent += double(l_out[el.front_patch].s[c]) * counts[e] * bin_area;
      }
      ASSERT_GT(sent, 0.0);
      EXPECT_NEAR(received / sent, 1.0, tolerance) << "iteration " << t << " channel " << c;
    }
  }
}

TEST(RayBundleAnalytic, ClosedSceneReceivesExactlyThePowerThatLeaves) { expect_closed_scene_power_balance(0.0f, 1e-5); }

TEST(RayBundleAnalytic, ClosedSceneWithTouchingSurfacesKeepsItsPowerBalance) {
  expect_closed_scene_power_balance(kContactDepthFraction, 2e-3);
}

// Small scenes size the tiled fragment buffers for every slot; large ones read each iteration's
// fragment count back and grow them (here from the first iteration on): both give the same radiance.
TEST(RayBundlePass, ReadBackFragmentBuffersGiveTheSameRadianceAsStaticOnes) {
  SceneMaterial m;
  m.kd = glm::vec3(0.5f);
  m.emission = glm::vec3(0.2f, 0.4f, 0.6f);
  const Scene scene = make_closed_box(1.0f, m);
  auto fixed = make_bundle_rig(scene, 0.2f, 48, 3u);
  auto grown = make_bundle_rig(scene, 0.2f, 48, 3u, 8, 8, 0, 0);
  for (int t = 0; t < 12; ++t) {
    fixed->pass->iterate(std::uint64_t(t));
    grown->pass->iterate(std::uint64_t(t));
  }
  const std::vector<cl_float4> a = fixed->pass->read_patch_irradiance(), b = grown->pass->read_patch_irradiance();
  ASSERT_EQ(a.size(), b.size());
  double total = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 4; ++c) {
      EXPECT_EQ(a[i].s[c], b[i].s[c]) << "patch " << i;
      total += a[i].s[c];
    }
  EXPECT_GT(total, 0.0);
}

// Closed box, every surface emitting Le with Lambert albedo a: every pixel of the eye estimate
// converges to Le / (1 - a). Independent seeds give the standard error (iterations of one run are
// correlated); the warm-up leaves a^W of the answer missing, negligible here.
TEST(RayBundleAnalytic, FurnaceImageIsLeOverOneMinusAlbedo) {
  const double albedo = 0.7, le = 0.5, expected = le / (1.0 - albedo);
  SceneMaterial m;
  m.kd = glm::vec3(float(albedo));
  m.emission = glm::vec3(float(le));
  const std::uint32_t warmup = std::uint32_t(std::ceil(std::log(1e-7) / std::log(albedo)));
  const int runs = 6;
  std::vector<double> means;
  for (int k = 0; k < runs; ++k) {
    auto rig = make_bundle_rig(make_closed_box(1.0f, m), 0.25f, 64, 100u + k, 16, 16, warmup);
    RenderRun run = render_rb(*rig, 200);
    EXPECT_EQ(run.outcome.nonfinite_samples, 0u);
    means.push_back(std::accumulate(run.image.rgb.begin(), run.image.rgb.end(), 0.0) / run.image.rgb.size());
  }
  double mean = std::accumulate(means.begin(), means.end(), 0.0) / runs, var = 0.0;
  for (double m2 : means) var += (m2 - mean) * (m2 - mean) / (runs - 1);
  double t = (mean - expected) / std::sqrt(var / runs);
  EXPECT_GT(student_t_two_sided_p(t, runs - 1), 0.01) << "mean " << mean << " expected " << expected;
  EXPECT_NEAR(mean / expected, 1.0, 0.02);
}

// A black decal 0.1 mm in front of the receiver of make_parallel_squares covers x < cut. A patch it
// partly covers must receive what its open part receives -- about what the same patch receives
// without the decal -- not that times its open fraction (kContactDepthFraction). Same seed with and
// without the decal: the same directions and bin offsets, so the ratio is tight.
TEST(RayBundleAnalytic, PatchPartlyCoveredByATouchingSurfaceReceivesWhatItsOpenPartDoes) {
  const float side = 1.0f, distance = 0.2f, patch_size = 0.1f, cut = 0.52f, gap = 1e-4f;  // the cut off the k = 15 grid (multiples of 1/15)
  const Scene open = make_parallel_squares(side, distance, 1.0f);
  Scene covered = open;
  SceneMaterial black;
  black.kd = glm::vec3(0.0f);
  covered.materials.push_back(black);  // material 2, facing -z like the receiver
  const float z = distance - gap, x0 = -0.1f;
  covered.triangles.push_back({{{x0, 0, z}, {cut, side, z}, {cut, 0, z}}, 2});
  covered.triangles.push_back({{{x0, 0, z}, {x0, side, z}, {cut, side, z}}, 2});
  for (const SceneTriangle& t : covered.triangles)
    for (const glm::vec3& p : t.p) covered.bounds.grow(p);
  // Both rigs on the same bounding sphere (the bin grid follows it): the decal stays inside the
  // receiver's bounds but for x0, so grow the open scene by the same point.
  Scene open_grown = open;
  open_grown.bounds = covered.bounds;
  auto with = make_bundle_rig(covered, patch_size, 200, 9u), without = make_bundle_rig(open_grown, patch_size, 200, 9u);
  // Receiver elements the cut crosses with between 30 % and 70 % of their area covered, away from
  // the squares' edges (where the irradiance falls across a patch).
  std::vector<std::uint32_t> partly;
  for (const BundleElement& el : with->geometry.elements) {
    if (el.material != 1) continue;
    int inside = 0, n = 0;
    for (int i = 0; i < 40; ++i)
      for (int j = 0; i + j < 40; ++j, ++n) {
        const float b1 = (i + 0.33f) / 40.0f, b2 = (j + 0.33f) / 40.0f;
        inside += el.v0[0] + b1 * el.e1[0] + b2 * el.e2[0] < cut;
      }
    const float y = el.v0[1] + (el.e1[1] + el.e2[1]) / 3.0f;
    if (inside > 0.3 * n && inside < 0.7 * n && y > 0.25f && y < 0.75f) partly.push_back(el.front_patch);
  }
  ASSERT_GE(partly.size(), 6u);
  const int iterations = 300;
  std::vector<double> ratio_per_iteration;
  for (int t = 0; t < iterations; ++t) {
    with->pass->iterate(std::uint64_t(t));
    without->pass->iterate(std::uint64_t(t));
    const std::vector<cl_float4> a = with->pass->read_patch_irradiance(), b = without->pass->read_patch_irradiance();
    double sa = 0.0, sb = 0.0;
    for (std::uint32_t p : partly) {
      sa += a[p].s[0];
      sb += b[p].s[0];
    }
    if (sb > 0.0) ratio_per_iteration.push_back(sa / sb);
  }
  const double n = double(ratio_per_iteration.size());
  double mean = std::accumulate(ratio_per_iteration.begin(), ratio_per_iteration.end(), 0.0) / n, var = 0.0;
  for (double r : ratio_per_iteration) var += (r - mean) * (r - mean) / (n - 1);
  // Not exactly 1 (the open part's own mean, a few % of slope across a patch; grazing directions,
  // where 0.1 mm along omega exceeds the contact depth): within 6 %. Without the rule it is about 0.5.
  EXPECT_NEAR(mean, 1.0, 0.06) << "standard error " << std::sqrt(var / n) << " over " << partly.size() << " patches";
}

TEST(RayBundle, SameSeedSameImage) {
  Scene scene = make_parallel_squares(1.0f, 1.0f, 2.0f);
  scene.materials[1].kd = glm::vec3(0.5f);  // the camera sits between the squares, facing the receiver
  auto a = make_bundle_rig(scene, 0.2f, 50, 3u, 12, 12, 2);
  auto b = make_bundle_rig(scene, 0.2f, 50, 3u, 12, 12, 2);
  RenderRun ra = render_rb(*a, 40), rb = render_rb(*b, 40);
  EXPECT_EQ(ra.image.rgb, rb.image.rgb);
  double sum = std::accumulate(ra.image.rgb.begin(), ra.image.rgb.end(), 0.0);
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace bp::test

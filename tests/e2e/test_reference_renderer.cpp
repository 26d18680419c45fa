// The independent reference renderer checked against cases whose answer is known exactly.
#include "e2e/reference_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace {

using glm::vec3;

// Two triangles a-b-c, a-c-d, wound so that their front faces the side `facing` points to.
void add_quad(bp::Scene& scene, vec3 a, vec3 b, vec3 c, vec3 d, vec3 facing, std::uint32_t material) {
  if (glm::dot(glm::cross(b - a, c - a), facing) < 0.0f) std::swap(b, d);
  scene.triangles.push_back({{a, b, c}, material});
  scene.triangles.push_back({{a, c, d}, material});
}

// Axis-aligned box [lo, hi]; faces point inward (a room) or outward (a block).
void add_box(bp::Scene& scene, vec3 lo, vec3 hi, bool inward, std::uint32_t material) {
  const float s = inward ? -1.0f : 1.0f;
  const vec3 c = 0.5f * (lo + hi);
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      vec3 p[4];
      for (int k = 0; k < 4; ++k) {
        p[k] = c;
        p[k][axis] = side ? hi[axis] : lo[axis];
        p[k][u] = (k == 1 || k == 2) ? hi[u] : lo[u];
        p[k][v] = (k >= 2) ? hi[v] : lo[v];
      }
      vec3 facing(0.0f);
      facing[axis] = (side ? 1.0f : -1.0f) * s;
      add_quad(scene, p[0], p[1], p[2], p[3], facing, material);
    }
  }
}

bp::SceneMaterial material(vec3 kd, vec3 emission = vec3(0.0f), bool double_sided = false) {
  bp::SceneMaterial m;
  m.kd = kd;
  m.emission = emission;
  m.double_sided = double_sided;
  return m;
}

// Two-sided normal quantile by bisection on erfc: P(|Z| > z) = alpha.
double two_sided_z(double alpha) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
  }
  return lo;
}

struct ZTest {
  double image_z = 0.0;    // z of the image-wide mean
  double max_pixel_z = 0.0;
  double pixel_limit = 0.0;  // Šidák-corrected |z| limit for alpha = 0.01 over all pixel channels
};

// Every pixel channel against expected[c], using the renderer's own standard errors.
ZTest z_against(const bp::ReferenceResult& r, const glm::dvec3& expected) {
  ZTest z;
  double sum_diff = 0.0, sum_var = 0.0;
  const std::size_t n = r.mean.rgb.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double diff = r.mean.rgb[i] - expected[int(i % 3)], se = r.std_error.rgb[i];
    sum_diff += diff;
    sum_var += se * se;
    z.max_pixel_z = std::max(z.max_pixel_z, se > 0.0 ? std::abs(diff) / se : (diff == 0.0 ? 0.0 : 1e30));
  }
  z.image_z = sum_var > 0.0 ? std::abs(sum_diff) / std::sqrt(sum_var) : (sum_diff == 0.0 ? 0.0 : 1e30);
  z.pixel_limit = two_sided_z(1.0 - std::pow(1.0 - 0.01, 1.0 / double(n)));
  return z;
}

// A closed room whose every wall emits Le and reflects diffusely with albedo a: the radiance is
// Le/(1-a) everywhere (L = Le + a L), whatever the room's shape.
bp::Scene furnace(vec3 Le, vec3 albedo) {
  bp::Scene scene;
  scene.materials.push_back(material(albedo, Le));
  add_box(scene, vec3(-1.0f, -0.7f, -1.3f), vec3(1.2f, 0.9f, 0.8f), /*inward=*/true, 0);
  scene.camera.position = vec3(0.1f, 0.0f, 0.2f);
  scene.camera.forward = glm::normalize(vec3(0.3f, -0.2f, -1.0f));
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 1.6f;  // wide, so that pixels see several walls, edges and corners
  return scene;
}

struct FurnaceRun {
  bp::ReferenceResult result;
  glm::dvec3 expected, mean;
  ZTest z;
};

FurnaceRun run_furnace(bp::ReferenceEstimator estimator, int width, int height, int spp) {
  const vec3 Le(1.0f, 0.5f, 0.25f), albedo(0.5f, 0.3f, 0.7f);
  FurnaceRun run{bp::render_reference(furnace(Le, albedo), width, height, spp, 7, {estimator}),
                 glm::dvec3(Le) / (1.0 - glm::dvec3(albedo)), glm::dvec3(0.0), {}};
  run.z = z_against(run.result, run.expected);
  const std::size_t pixels = std::size_t(width) * height;
  for (std::size_t i = 0; i < run.result.mean.rgb.size(); ++i) run.mean[int(i % 3)] += run.result.mean.rgb[i] / pixels;
  std::printf("furnace %dx%d %d spp: mean %.4f %.4f %.4f (expect %.4f %.4f %.4f), image z %.2f, "
              "max pixel |z| %.2f (limit %.2f), %.2f s\n", width, height, spp, run.mean[0], run.mean[1],
              run.mean[2], run.expected[0], run.expected[1], run.expected[2], run.z.image_z, run.z.max_pixel_z,
              run.z.pixel_limit, run.result.seconds);
  return run;
}

// The Cornell box (classic dimensions in metres), open at the front; a glossy tall block.
bp::Scene cornell_box() {
  bp::Scene scene;
  scene.materials = {material(vec3(0.73f)), material(vec3(0.63f, 0.065f, 0.05f)),
                     material(vec3(0.14f, 0.45f, 0.091f)), material(vec3(0.78f), vec3(17.0f, 12.0f, 4.0f)),
                     material(vec3(0.4f))};
  scene.materials[4].ks = vec3(0.35f);
  scene.materials[4].shininess = 30.0f;
  const float w = 0.555f;
  add_quad(scene, {0, 0, 0}, {w, 0, 0}, {w, 0, -w}, {0, 0, -w}, {0, 1, 0}, 0);  // floor
  add_quad(scene, {0, w, 0}, {w, w, 0}, {w, w, -w}, {0, w, -w}, {0, -1, 0}, 0);  // ceiling
  add_quad(scene, {0, 0, -w}, {w, 0, -w}, {w, w, -w}, {0, w, -w}, {0, 0, 1}, 0);  // back
  add_quad(scene, {0, 0, 0}, {0, 0, -w}, {0, w, -w}, {0, w, 0}, {1, 0, 0}, 1);  // left, red
  add_quad(scene, {w, 0, 0}, {w, 0, -w}, {w, w, -w}, {w, w, 0}, {-1, 0, 0}, 2);  // right, green
  const float ly = w - 0.001f;
  add_quad(scene, {0.213f, ly, -0.227f}, {0.343f, ly, -0.227f}, {0.343f, ly, -0.332f}, {0.213f, ly, -0.332f},
           {0, -1, 0}, 3);                                                                      // light
  add_box(scene, {0.13f, 0.0f, -0.24f}, {0.29f, 0.165f, -0.08f}, false, 0);                       // short block
  add_box(scene, {0.29f, 0.0f, -0.45f}, {0.45f, 0.33f, -0.29f}, false, 4);                        // tall block
  scene.camera.position = {0.2775f, 0.2775f, 0.8f};
  scene.camera.forward = {0, 0, -1};
  scene.camera.up = {0, 1, 0};
  scene.camera.yfov = 0.6911f;
  return scene;
}

}  // namespace

// Pure hemisphere sampling is a bounded estimator, so every pixel is z-tested. Enough samples per
// pixel are needed for that: path sums are skewed, and at a few hundred spp the sample standard
// error of a pixel that drew no long path underestimates the true one (z of -5 seen at 256 spp).
TEST(ReferenceRenderer, FurnaceEveryPixelIsLeOverOneMinusAlbedo) {
  const FurnaceRun run = run_furnace(bp::ReferenceEstimator::hemisphere, 12, 8, 4096);
  EXPECT_LT(run.z.image_z, 4.0);
  EXPECT_LT(run.z.max_pixel_z, std::max(4.0, run.z.pixel_limit));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(run.mean[c], run.expected[c], 0.01 * run.expected[c]);
}

// With next-event estimation, points near an edge where two emitting walls meet see an unbounded
// 1/d^2 term: per-pixel variance is infinite there, so only the image-wide mean is tested. (The
// Cornell box's light touches no wall, and there the estimator has finite variance.)
TEST(ReferenceRenderer, FurnaceNextEventImageMean) {
  const FurnaceRun run = run_furnace(bp::ReferenceEstimator::hemisphere_nee, 24, 16, 256);
  EXPECT_LT(run.z.image_z, 4.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(run.mean[c], run.expected[c], 0.02 * run.expected[c]);
}

TEST(ReferenceRenderer, PhongIsReciprocalAndConservesAtNormalIncidence) {
  bp::SceneMaterial m = material(vec3(0.2f, 0.0f, 0.5f));
  m.ks = vec3(0.6f, 0.9f, 0.3f);
  m.shininess = 12.0f;
  const glm::dvec3 n(0, 0, 1);
  const glm::dvec3 a = glm::normalize(glm::dvec3(0.3, -0.2, 0.9)), b = glm::normalize(glm::dvec3(-0.25, 0.1, 0.7));
  const glm::dvec3 fab = bp::reference_detail::phong_brdf(m, n, a, b), fba = bp::reference_detail::phong_brdf(m, n, b, a);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fab[c], fba[c], 1e-12);
  EXPECT_EQ(bp::reference_detail::phong_brdf(m, n, a, -b), glm::dvec3(0.0));  // below the surface
  // Seen along the normal, the lobe integrates to ks and the diffuse part to kd (midpoint rule).
  const int steps = 2000;
  glm::dvec3 albedo(0.0);
  for (int i = 0; i < steps; ++i) {
    const double theta = (i + 0.5) * (std::numbers::pi / 2) / steps;
    const glm::dvec3 wi(std::sin(theta), 0.0, std::cos(theta));
    albedo += bp::reference_detail::phong_brdf(m, n, n, wi) * std::cos(theta) * std::sin(theta) *
              (2.0 * std::numbers::pi * (std::numbers::pi / 2) / steps);
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(albedo[c], double(m.kd[c] + m.ks[c]), 1e-5);
}

TEST(ReferenceRenderer, CameraPutsTheTopRowAtYZeroAndRightAtPositiveX) {
  // A wall of four emitting quadrants straight ahead, filling the view; pixels see Le exactly.
  bp::Scene scene;
  const vec3 colours[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};  // TL, TR, BL, BR
  for (int q = 0; q < 4; ++q) {
    scene.materials.push_back(material(vec3(0.0f), colours[q]));
    const float x0 = (q % 2) ? 0.0f : -10.0f, y0 = (q < 2) ? 0.0f : -10.0f;
    add_quad(scene, {x0, y0, -1}, {x0 + 10, y0, -1}, {x0 + 10, y0 + 10, -1}, {x0, y0 + 10, -1}, {0, 0, 1}, q);
  }
  const bp::ReferenceResult r = bp::render_reference(scene, 8, 6, 4, 1);
  auto expect_pixel = [&](int x, int y, vec3 c) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r.mean.pixel(x, y)[k], c[k]) << x << "," << y;
  };
  expect_pixel(0, 0, colours[0]);
  expect_pixel(7, 0, colours[1]);
  expect_pixel(0, 5, colours[2]);
  expect_pixel(7, 5, colours[3]);
  for (float e : r.std_error.rgb) EXPECT_EQ(e, 0.0f);
}

TEST(ReferenceRenderer, EmittersAndSurfacesAreOneSidedUnlessDoubleSided) {
  for (bool double_sided : {false, true}) {
    for (auto estimator : {bp::ReferenceEstimator::hemisphere, bp::ReferenceEstimator::hemisphere_nee}) {
      // An emitter facing away from the camera.
      bp::Scene away;
      away.materials.push_back(material(vec3(0.5f), vec3(3.0f), double_sided));
      add_quad(away, {-5, -5, -1}, {5, -5, -1}, {5, 5, -1}, {-5, 5, -1}, {0, 0, -1}, 0);
      const bp::ReferenceResult e = bp::render_reference(away, 4, 4, 2, 3, {estimator});
      EXPECT_EQ(e.mean.pixel(2, 2)[0], double_sided ? 3.0f : 0.0f);

      // A white wall whose back faces the camera, lit by an emitter facing it behind the camera.
      bp::Scene back;
      back.materials = {material(vec3(0.9f), vec3(0.0f), double_sided), material(vec3(0.0f), vec3(1.0f))};
      add_quad(back, {-5, -5, -1}, {5, -5, -1}, {5, 5, -1}, {-5, 5, -1}, {0, 0, -1}, 0);
      add_quad(back, {-5, -5, 1}, {5, -5, 1}, {5, 5, 1}, {-5, 5, 1}, {0, 0, -1}, 1);
      const bp::ReferenceResult b = bp::render_reference(back, 4, 4, 64, 3, {estimator});
      if (double_sided) EXPECT_GT(b.mean.pixel(2, 2)[0], 0.1f);
      else EXPECT_EQ(b.mean.pixel(2, 2)[0], 0.0f);
    }
  }
}

TEST(ReferenceRenderer, IsDeterministicWhateverTheThreadCount) {
  const bp::Scene scene = cornell_box();
  const bp::ReferenceResult one = bp::render_reference(scene, 12, 10, 4, 99, {bp::ReferenceEstimator::hemisphere_nee, 1});
  const bp::ReferenceResult two = bp::render_reference(scene, 12, 10, 4, 99, {bp::ReferenceEstimator::hemisphere_nee, 2});
  EXPECT_EQ(one.mean.rgb, two.mean.rgb);
  EXPECT_EQ(one.std_error.rgb, two.std_error.rgb);
}

TEST(ReferenceRenderer, CornellNextEventAgreesWithPureHemisphereSampling) {
  // Two estimators of the same integral, with independent seeds: 4x4 blocks must agree.
  const bp::Scene scene = cornell_box();
  const int w = 32, h = 32;
  const bp::ReferenceResult nee = bp::render_reference(scene, w, h, 16, 11, {bp::ReferenceEstimator::hemisphere_nee});
  const bp::ReferenceResult hemi = bp::render_reference(scene, w, h, 128, 12, {bp::ReferenceEstimator::hemisphere});
  std::printf("cornell %dx%d: next-event %d spp %.2f s (%.0f paths/s), hemisphere %d spp %.2f s (%.0f paths/s)\n", w, h,
              16, nee.seconds, nee.paths / nee.seconds, 128, hemi.seconds, hemi.paths / hemi.seconds);
  const int block = 8, blocks = (w / block) * (h / block) * 3;
  const double limit = two_sided_z(1.0 - std::pow(0.99, 1.0 / blocks));
  double worst = 0.0, sum_nee = 0.0, sum_hemi = 0.0, var_sum = 0.0;
  for (int by = 0; by < h / block; ++by)
    for (int bx = 0; bx < w / block; ++bx)
      for (int c = 0; c < 3; ++c) {
        double a = 0.0, b = 0.0, var = 0.0;
        for (int y = by * block; y < (by + 1) * block; ++y)
          for (int x = bx * block; x < (bx + 1) * block; ++x) {
            a += nee.mean.pixel(x, y)[c];
            b += hemi.mean.pixel(x, y)[c];
            var += std::pow(nee.std_error.pixel(x, y)[c], 2) + std::pow(hemi.std_error.pixel(x, y)[c], 2);
          }
        worst = std::max(worst, std::abs(a - b) / std::sqrt(var));
        sum_nee += a;
        sum_hemi += b;
        var_sum += var;
      }
  const double image_z = std::abs(sum_nee - sum_hemi) / std::sqrt(var_sum);
  std::printf("cornell: mean next-event %.4f, hemisphere %.4f, image z %.2f, worst block z %.2f (limit %.2f)\n",
              sum_nee / (w * h * 3), sum_hemi / (w * h * 3), image_z, worst, limit);
  EXPECT_LT(image_z, 4.0);
  EXPECT_LT(worst, limit);
}

// The path tracer at numerical extremes: Phong shininess 0 / 1e4 / 1e6, albedo 0.999 (paths of
// ~1000 vertices), grazing views, scenes scaled by 1e-3 and 1e4, hundreds of sharp-lobe bounces,
// and the log-domain q/r state of eq. (9) over 1000-step products. Every image must be finite
// (no sample dropped as NaN/Inf) and match a value derived here, with a tolerance from its variance.
#include "e2e/reference_renderer.h"
#include "kernel/device_fixture.h"
#include "stats.h"

#include "kernels/shared/brdf.h"
#include "kernels/shared/path_pdf.h"
#include "kernels/shared/rng.h"

#include <gtest/gtest.h>
#include <cmath>
#include <string>

namespace bp::test {
namespace {

// These tests count rays: with light sampling off every ray is one vertex of a BSDF-sampled path,
// so the furnace identity "radiance = Le x rays" and the path-length statistics hold exactly.
// Light sampling in the furnace is tested in tests/kernel (PathTraceFurnace).
RenderRun render_bsdf_sampled(const Scene& scene, int width, int height, std::uint64_t spp, std::uint32_t seed) {
  return render_pt(scene, width, height, spp, seed, 65536, false);
}

// Every statistical check in this file is one test of a family of this size, so that the whole
// file fails by chance with probability at most 0.01 (Šidák).
// Shininess 3 + 2 + 2, depth 2 + 1, grazing 1, scale 4.
constexpr int kStatisticalChecks = 15;
double z_limit() { return z_for_two_sided(sidak_alpha(0.01, kStatisticalChecks)); }

SceneMaterial emitting(glm::vec3 kd, glm::vec3 ks, float shininess, float le) {
  SceneMaterial m;
  m.kd = kd;
  m.ks = ks;
  m.shininess = shininess;
  m.emission = glm::vec3(le);
  return m;
}

// A closed axis-aligned box centre ± half seen from inside (inward normals), camera at `eye`.
Scene make_box(glm::vec3 centre, glm::vec3 half, const SceneMaterial& material, glm::vec3 eye, glm::vec3 forward,
               glm::vec3 up, float yfov) {
  Scene scene;
  scene.materials.push_back(material);
  glm::vec3 c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = centre + half * glm::vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
  // Quads counter-clockwise seen from inside: -z, +z, -x, +x, -y, +y.
  const int faces[6][4] = {{0, 1, 3, 2}, {5, 4, 6, 7}, {4, 0, 2, 6}, {1, 5, 7, 3}, {4, 5, 1, 0}, {2, 3, 7, 6}};
  for (const auto& f : faces) {
    scene.triangles.push_back({{c[f[0]], c[f[1]], c[f[2]]}, 0});
    scene.triangles.push_back({{c[f[0]], c[f[2]], c[f[3]]}, 0});
  }
  for (const SceneTriangle& t : scene.triangles) {
    const glm::vec3 inward = centre - (t.p[0] + t.p[1] + t.p[2]) / 3.0f;
    EXPECT_GT(glm::dot(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]), inward), 0.0f) << "box face not inward";
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  }
  scene.camera.position = eye;
  scene.camera.forward = glm::normalize(forward);
  scene.camera.up = up;
  scene.camera.yfov = yfov;
  return scene;
}

// Mean over pixels and channels, in double.
double image_mean(const ImageRGB& image) {
  double sum = 0.0;
  for (float v : image.rgb) sum += v;
  return sum / double(image.rgb.size());
}

void expect_finite(const RenderRun& run, const std::string& what) {
  EXPECT_EQ(run.outcome.nonfinite_samples, 0u) << what;
  for (float v : run.image.rgb) {
    ASSERT_TRUE(std::isfinite(v)) << what << ": a non-finite pixel";
    ASSERT_GE(v, 0.0f) << what << ": a negative pixel";
  }
}

// Lambert furnace (kd = a, ks = 0 or any, Le everywhere, s = a): every sample is exactly Le times
// its vertex count K ~ Geometric(1 - a), so the pixel mean is Le/(1-a) with per-sample standard
// deviation Le sqrt(a)/(1-a). Each vertex costs exactly one ray and every ray hits, so also
// sum of radiance = Le * rays: a ray that leaks through the box or hits a back face (a failed
// offset) adds a ray without adding Le, which that identity sees even below the noise.
void expect_lambert_furnace(const RenderRun& run, double albedo, double le, std::uint64_t spp,
                            const std::string& what) {
  expect_finite(run, what);
  const double samples = double(run.image.width) * run.image.height * double(spp);
  const double mean = image_mean(run.image);
  const double expected = le / (1.0 - albedo);
  const double sd = le * std::sqrt(albedo) / (1.0 - albedo);
  EXPECT_LT(std::fabs(mean - expected) / (sd / std::sqrt(samples)), z_limit())
      << what << ": mean " << mean << ", expected " << expected;
  // The throughput is 1 only up to the float rounding of f cos / (s p), a few 2^-24 per vertex,
  // which compounds along the path: vertex k is off by up to ~k 2^-22, and averaged over the
  // geometric vertex count that is 2^-22 E[K^2] / (2 E[K]) = 2^-22 (1 + a) / (2 (1 - a)) (measured
  // here: 0 at a = 0.8, 8e-5 at a = 0.999). A leaked ray loses Le (1 + the rest of its path).
  const double rounding = 1e-6 + std::ldexp(1.0, -22) * (1.0 + albedo) / (2.0 * (1.0 - albedo));
  const double radiance_per_ray = mean * samples / (le * double(run.outcome.rays));
  EXPECT_NEAR(radiance_per_ray, 1.0, rounding) << what << ": rays " << run.outcome.rays << " for " << samples
                                           << " samples (some ray leaked or hit a back face)";
}

// ------------------------------------------------------------------ shininess 0, 1e4, 1e6

// kd = a, ks = 0: the shininess is never sampled, the furnace is exact, and the lobe terms that
// meet n = 1e6 (pow of a cosine near 1, (n+2)/(2 pi)) must not turn 0 * large into NaN.
TEST(PtExtremesShininess, LambertFurnaceIsExactForAnyShininess) {
  for (float n : {0.0f, 1e4f, 1e6f}) {
    Scene scene = make_closed_box(1.0f, emitting(glm::vec3(0.6f), glm::vec3(0.0f), n, 1.0f));
    RenderRun run = render_bsdf_sampled(scene, 16, 16, 32, 11u);
    expect_lambert_furnace(run, 0.6, 1.0, 32, "kd 0.6, shininess " + std::to_string(n));
  }
}

// Pure specular walls (kd 0, ks = a) in a slab |x|,|y| <= 50, |z| <= 1, seen along -z at normal
// incidence through a 0.02 rad field of view, so a path ping-pongs between the two big walls.
// With s = a every bounce multiplies the throughput by w = (n+2)/(n+1) cos(theta_i), and for a lobe
// that lies above the horizon E[w | theta_o] = cos(theta_o) exactly (the cos(alpha) cos(theta_o)
// part of cos(theta_i) integrates to cos(theta_o), the azimuthal part to 0). Mirror reflection
// keeps the transverse part t of the direction and each lobe sample adds an independent kick with
// E|kick|^2 = E[sin^2 alpha] = 2/(n+3). To first order in 1/n and |t0|^2:
//   E[w_1 ... w_k] = 1 - k(k-1)/(2n) - k |t0|^2 / 2,
//   pixel = Le sum_k a^k E[...] = Le [1/(1-a) - a^2/(n (1-a)^3) - a |t0|^2 / (2 (1-a)^2)].
// The lateral drift after k bounces is ~2 sqrt(2/n) k^1.5 (2/3), so a path reaches the slab's side
// walls only after ~190 bounces at n = 1e4 (0.5^190) and ~880 at n = 1e6 (0.99^880 ~ 1e-4).
double specular_slab_expected(double a, double n, double le, double t0_squared) {
  return le * (1.0 / (1.0 - a) - a * a / (n * std::pow(1.0 - a, 3)) - a * t0_squared / (2.0 * (1.0 - a) * (1.0 - a)));
}

Scene specular_slab(float albedo, float shininess, float le, float yfov) {
  return make_box(glm::vec3(0.0f), glm::vec3(50.0f, 50.0f, 1.0f),
                  emitting(glm::vec3(0.0f), glm::vec3(albedo), shininess, le), glm::vec3(0.0f),
                  glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0.0f, 1.0f, 0.0f), yfov);
}

// Pixel means are independent with a common expectation (the |t0|^2 term varies by < 1e-4 of it
// across the image), so their spread estimates the standard error: a t-test with P-1 dof.
void expect_pixel_mean_t(const ImageRGB& image, double expected, const std::string& what) {
  const int pixels = image.width * image.height;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < pixels; ++i) {
    const float* p = &image.rgb[std::size_t(i) * 3];
    const double v = (double(p[0]) + p[1] + p[2]) / 3.0;
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / pixels;
  const double var = (sum2 - pixels * mean * mean) / (pixels - 1);
  const double t = (mean - expected) / std::sqrt(var / pixels);
  EXPECT_GT(student_t_two_sided_p(t, pixels - 1), sidak_alpha(0.01, kStatisticalChecks))
      << what << ": mean " << mean << ", expected " << expected << ", t " << t;
}

TEST(PtExtremesShininess, SharpSpecularLobesKeepTheirAlbedo) {
  const double a = 0.5, le = 1.0;
  const float yfov = 0.02f;
  const double t0_max = std::tan(0.5 * yfov) * std::sqrt(2.0);  // image corner
  for (float n : {1e4f, 1e6f}) {
    RenderRun run = render_bsdf_sampled(specular_slab(float(a), n, float(le), yfov), 16, 16, 64, 5u);
    const std::string what = "ks 0.5, shininess " + std::to_string(n);
    expect_finite(run, what);
    // Use the image-average |t0|^2 (a third of the corner's value for a square field of view).
    expect_pixel_mean_t(run.image, specular_slab_expected(a, n, le, t0_max * t0_max / 3.0), what);
  }
}

// Shininess 0: the lobe cos^0(alpha) = 1 makes its support matter. The reference renderer and
// bsdf_evaluate take the lobe as 0 where cos(alpha) <= 0 (the directional albedo of ks alone
// is then ks (1 + cos theta_o)/2, not ks: no closed form for a box), so compare with the
// independent reference renderer, which shares nothing with the kernel but the Scene.
// Two PT runs with different seeds give the PT variance from their difference (P pixels, exact
// for any per-pixel expectation); the reference reports its own per-pixel standard error.
void expect_matches_reference(const Scene& scene, const std::string& what) {
  const int w = 8, h = 8;
  const std::uint64_t spp = 512;
  RenderRun a = render_bsdf_sampled(scene, w, h, spp, 21u), b = render_bsdf_sampled(scene, w, h, spp, 22u);
  expect_finite(a, what);
  expect_finite(b, what);
  ReferenceOptions options;
  options.estimator = ReferenceEstimator::hemisphere;  // every wall emits: hitting them is efficient
  ReferenceResult ref = render_reference(scene, w, h, 2048, 7u, options);
  double pt_sum = 0.0, pt_var = 0.0, ref_sum = 0.0, ref_var = 0.0;
  const std::size_t n = a.image.rgb.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double d = double(a.image.rgb[i]) - b.image.rgb[i];
    pt_sum += 0.5 * (double(a.image.rgb[i]) + b.image.rgb[i]);
    pt_var += d * d / 4.0;  // Var((A+B)/2) = Var(A)/2, and E[(A-B)^2] = 2 Var(A)
    ref_sum += ref.mean.rgb[i];
    ref_var += double(ref.std_error.rgb[i]) * ref.std_error.rgb[i];
  }
  // The three channels are identical here, so count pixels once for the variance of the mean:
  // Var(sum of n values) is 3x what the sum of per-channel variances says when channels coincide.
  const double pt_mean = pt_sum / double(n), ref_mean = ref_sum / double(n);
  const double se = std::sqrt(3.0 * (pt_var + ref_var)) / double(n);
  EXPECT_LT(std::fabs(pt_mean - ref_mean) / se, z_limit())
      << what << ": PT " << pt_mean << ", reference " << ref_mean << " (standard error " << se << ")";
}

// Pure specular, and the same lobe beside a diffuse one: the diffuse lobe also samples directions
// with cos(alpha) <= 0, where the estimate then uses bsdf_eval's value of the Phong term.
TEST(PtExtremesShininess, ZeroMatchesReference) {
  expect_matches_reference(make_closed_box(1.0f, emitting(glm::vec3(0.0f), glm::vec3(0.5f), 0.0f, 1.0f)),
                           "kd 0, ks 0.5, shininess 0");
  expect_matches_reference(make_closed_box(1.0f, emitting(glm::vec3(0.25f), glm::vec3(0.25f), 0.0f, 1.0f)),
                           "kd 0.25, ks 0.25, shininess 0");
}

// ------------------------------------------------------------------ long paths

// Albedo 0.999: mean path length 1000 vertices (max_depth stays at its 65536 default: the chance
// that a path reaches it is 0.999^65536 ~ 3e-29). 4096 samples give a 1.6% standard error.
TEST(PtExtremesDepth, Albedo0999Furnace) {
  const double a = 0.999, le = 0.001;
  Scene scene = make_closed_box(1.0f, emitting(glm::vec3(float(a)), glm::vec3(0.0f), 1.0f, float(le)));
  const std::uint64_t spp = 16;
  RenderRun run = render_bsdf_sampled(scene, 16, 16, spp, 17u);
  expect_lambert_furnace(run, a, le, spp, "albedo 0.999");
  // The mean vertex count is the geometric mean 1/(1-a) = 1000, sd sqrt(a)/(1-a) per path.
  const double samples = 16.0 * 16.0 * double(spp);
  const double per_path = double(run.outcome.rays) / samples;
  EXPECT_LT(std::fabs(per_path - 1000.0) / (std::sqrt(a) / (1.0 - a) / std::sqrt(samples)), z_limit())
      << "mean path length " << per_path;
}

// Hundreds of bounces on a sharp lobe (ks 0.99, shininess 1e6): q of eq. (9) grows by ~e^12.8 per
// vertex, past float's range after 7 of them, but the kernel keeps it in the log domain and the
// image (weights NONE in PT mode) must stay finite and equal the slab's derived value.
TEST(PtExtremesDepth, HundredsOfSharpBouncesStayFinite) {
  const double a = 0.99, n = 1e6, le = 0.01;
  const float yfov = 0.02f;
  RenderRun run = render_bsdf_sampled(specular_slab(float(a), float(n), float(le), yfov), 16, 16, 16, 29u);
  expect_finite(run, "ks 0.99, shininess 1e6");
  const double per_path = double(run.outcome.rays) / (16.0 * 16.0 * 16.0);
  EXPECT_GT(per_path, 50.0) << "paths should average ~100 vertices";
  const double t0 = std::tan(0.5 * yfov) * std::sqrt(2.0);
  expect_pixel_mean_t(run.image, specular_slab_expected(a, n, le, t0 * t0 / 3.0), "ks 0.99, shininess 1e6");
}

// ------------------------------------------------------------------ grazing views

// A black emitting square (Le, kd 0) seen from 1e-3 above it, looking level along it: the lower
// half of the image meets the plane at angles from 6e-6 to 2e-3 rad, and the rows whose rays
// travel ~7.5 m hit it next to the diagonal shared by its two triangles. A pixel all of whose rays
// hit the square reads exactly Le (throughput 1, kd 0 ends the path: no noise); one whose rays all
// run level or upwards reads 0. A ray that slips through the diagonal, or a grazing hit the
// triangle test loses, leaves a hitting row below Le.
void expect_grazing_emitter_exact() {
  const float half = 100.0f, height = 1e-3f, le = 3.0f;
  Scene scene;
  scene.materials.push_back(emitting(glm::vec3(0.0f), glm::vec3(0.0f), 1.0f, le));
  const glm::vec3 c[4] = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
  scene.triangles.push_back({{c[0], c[1], c[2]}, 0});  // front (+z) faces up; the diagonal is y = x
  scene.triangles.push_back({{c[0], c[2], c[3]}, 0});
  for (const auto& t : scene.triangles)
    for (const auto& p : t.p) scene.bounds.grow(p);
  const float yfov = 4e-3f;
  const glm::dvec2 eye(-50.0, -55.0), heading = glm::normalize(glm::dvec2(0.3, 1.0));
  scene.camera.position = glm::vec3(float(eye.x), float(eye.y), height);
  scene.camera.forward = glm::vec3(float(heading.x), float(heading.y), 0.0f);
  scene.camera.up = glm::vec3(0, 0, 1);
  scene.camera.yfov = yfov;
  const int w = 16, h = 64;
  RenderRun run = render_bsdf_sampled(scene, w, h, 16, 3u);
  expect_finite(run, "grazing emitter");
  // camera.h: row py spans screen offsets sy = 2 (py + jy)/h - 1 in [2 py/h - 1, 2 (py+1)/h - 1];
  // a ray descends by sy tan(yfov/2) per unit of horizontal travel (to 1e-6, the columns span
  // +-1e-3 rad), so it meets z = 0 after height / (sy tan) unless it leaves the square first, at
  // the edge y = half after (half - eye.y) / heading.y (the edge x = half is three times further).
  const double tan_y = std::tan(0.5 * double(yfov));
  const double reach = 0.99 * (half - eye.y) / heading.y;
  int exact_rows = 0, empty_rows = 0;
  for (int py = 0; py < h; ++py) {
    const double shallowest = (2.0 * py / h - 1.0) * tan_y, steepest = (2.0 * (py + 1) / h - 1.0) * tan_y;
    const bool all_hit = shallowest > 0.0 && height / shallowest < reach;
    const bool none_hit = steepest <= 0.0;
    for (int px = 0; px < w; ++px) {
      const float* v = run.image.pixel(px, py);
      for (int ch = 0; ch < 3; ++ch) {
        if (all_hit) EXPECT_EQ(v[ch], le) << "pixel " << px << "," << py << " (hits at " << height / steepest
                                          << " .. " << height / shallowest << " m)";
        else if (none_hit) EXPECT_EQ(v[ch], 0.0f) << "pixel " << px << "," << py;
        else EXPECT_LE(v[ch], le) << "pixel " << px << "," << py;
      }
    }
    exact_rows += all_hit;
    empty_rows += none_hit;
  }
  EXPECT_EQ(exact_rows, h / 2 - 1);  // all but the row at the horizon
  EXPECT_EQ(empty_rows, h / 2);
}

// The furnace seen from 1e-4 above its floor, looking along it: most rays hit the floor at angles
// of 1e-4 .. 0.1 rad, and every path then leaves from a grazing hit point.
void expect_grazing_furnace() {
  const double a = 0.5, le = 1.0;
  Scene scene = make_box(glm::vec3(0.0f), glm::vec3(1.0f), emitting(glm::vec3(float(a)), glm::vec3(0.0f), 1.0f, 1.0f),
                         glm::vec3(0.0f, -1.0f + 1e-4f, 0.9f), glm::vec3(0.0f, -0.02f, -1.0f),
                         glm::vec3(0.0f, 1.0f, 0.0f), 0.2f);
  const std::uint64_t spp = 64;
  RenderRun run = render_bsdf_sampled(scene, 16, 16, spp, 9u);
  expect_lambert_furnace(run, a, le, spp, "grazing furnace");
}

TEST(PtExtremesGeometry, GrazingViews) {
  expect_grazing_emitter_exact();
  expect_grazing_furnace();
}

// ------------------------------------------------------------------ scale

// The unit furnace scaled by 1e-3 and 1e4 (and moved 100 box sizes off the origin): radiance does not
// depend on scale, and with one material every path's vertex count depends on the RNG alone (the
// roulette draws), so as long as no ray leaks or self-intersects, every scale traces exactly the
// same number of rays and gives the same image up to float rounding. ray_epsilon_for sets the
// offsets (1e-5 of the diagonal, at least 3e-7 of the coordinates' magnitude). Scaling alone is
// exact at any scale; 1e3 box sizes or more off the origin, float positions lose rays at the box's
// edges (measured: 3e-5 of the radiance at 1e3, 2e-4 at 1e4, 2e-3 at 1e5), which no offset along
// the normal can prevent, so the moved box stays at 100.
TEST(PtExtremesGeometry, FurnaceIsScaleInvariant) {
  const double a = 0.8, le = 0.5;
  const std::uint64_t spp = 32;
  auto furnace = [&](float scale, glm::vec3 offset) {
    return make_box(offset, glm::vec3(scale), emitting(glm::vec3(float(a)), glm::vec3(0.0f), 1.0f, float(le)),
                    offset + scale * glm::vec3(0.1f, -0.05f, 0.02f), glm::vec3(0.3f, 0.2f, -1.0f),
                    glm::vec3(0.0f, 1.0f, 0.0f), 1.2f);
  };
  RenderRun unit = render_bsdf_sampled(furnace(1.0f, glm::vec3(0.0f)), 16, 16, spp, 4u);
  expect_lambert_furnace(unit, a, le, spp, "scale 1");
  struct Variant { const char* name; float scale; glm::vec3 offset; };
  for (const Variant& v : {Variant{"scale 1e-3", 1e-3f, glm::vec3(0.0f)}, Variant{"scale 1e4", 1e4f, glm::vec3(0.0f)},
                           Variant{"scale 1e4, 100 box sizes from the origin", 1e4f, glm::vec3(1e6f, -1e6f, 1e6f)}}) {
    RenderRun run = render_bsdf_sampled(furnace(v.scale, v.offset), 16, 16, spp, 4u);
    expect_finite(run, v.name);
    EXPECT_EQ(run.outcome.rays, unit.outcome.rays) << v.name << ": a different number of rays than at scale 1";
    double worst = 0.0;
    for (std::size_t i = 0; i < run.image.rgb.size(); ++i)
      worst = std::max(worst, std::fabs(double(run.image.rgb[i]) - unit.image.rgb[i]) / unit.image.rgb[i]);
    EXPECT_LT(worst, 1e-4) << v.name << ": largest relative pixel difference from scale 1";
    expect_lambert_furnace(run, a, le, spp, v.name);
  }
}

// ------------------------------------------------------------------ the q/r state on the host

// (9) in closed form for constant s and p: with x = s p, q_k = x^k and
// r_k = (1-s) sum_{j<k} x^j = (1-s) (x^k - 1)/(x - 1), evaluated in double in the log domain.
double log_r_closed_form(double s, double p, int k) {
  const double lx = std::log(s * p);
  if (lx > 0) return std::log1p(-s) + k * lx + std::log1p(-std::exp(-k * lx)) - std::log(std::expm1(lx));
  return std::log1p(-s) + std::log1p(-std::exp(k * lx)) - std::log(-std::expm1(lx));
}

TEST(PathPdfExtremes, ThousandStepProductsOfSharpAndFlatPdfs) {
  for (double s : {0.5, 0.999, 1.0}) {
    for (double p : {1e4, 1e-4}) {
      PathPdf pdf = path_pdf_start();
      for (int k = 1; k <= 1000; ++k) {
        path_pdf_step(&pdf, float(s), float(p));
        ASSERT_TRUE(std::isfinite(pdf.log_q)) << "s " << s << " p " << p << " step " << k;
        ASSERT_TRUE(std::isfinite(pdf.log_r)) << "s " << s << " p " << p << " step " << k;
      }
      const double log_q = 1000.0 * (std::log(double(float(s))) + std::log(double(float(p))));
      EXPECT_NEAR(pdf.log_q, log_q, 1e-4 * std::fabs(log_q)) << "s " << s << " p " << p;
      if (s < 1.0) {
        const double log_r = log_r_closed_form(double(float(s)), double(float(p)), 1000);
        EXPECT_NEAR(pdf.log_r, log_r, 1e-4 * std::max(1.0, std::fabs(log_r))) << "s " << s << " p " << p;
      } else {
        EXPECT_LE(pdf.log_r, BP_LOG_ZERO) << "s = 1 never terminates: r stays 0";
      }
      const float log_pstar = path_pdf_log_pstar(&pdf);
      ASSERT_TRUE(std::isfinite(log_pstar));
      for (float ratio : {1e-6f, 1.0f, 1e6f}) {
        const float w = pt_emission_weight(&pdf, BP_WEIGHTS_PAPER, ratio);
        ASSERT_TRUE(std::isfinite(w) && w >= 0.0f && w <= 1.0f) << "s " << s << " p " << p << " ratio " << ratio;
        // w_PT = 1 / (1 + N2/(N1 P*)) (4), with ln P* in double.
        const double expected = 1.0 / (1.0 + std::exp(std::log(double(ratio)) - double(log_pstar)));
        EXPECT_NEAR(w, expected, 1e-5) << "s " << s << " p " << p << " ratio " << ratio;
      }
    }
  }
}

// The kernel's own sharp-lobe walk on the host: 500 vertices of bsdf_sample on ks 0.99,
// shininess 1e6 between two parallel mirrors, stepping the pdf state with the sampled mixture
// densities (up to 1e6 each). ln q must track the double sum of the logs and everything must stay
// finite, though q itself left float's range after a handful of vertices.
TEST(PathPdfExtremes, SharpLobeWalkOfHundredsOfVertices) {
  Material m{};
  for (int c = 0; c < 3; ++c) m.ks[c] = 0.99f;
  m.shininess = 1e6f;
  const Bsdf bsdf = bsdf_from_material(&m);
  for (bp_u32 path = 0; path < 20; ++path) {
    Rng rng = rng_init(77u, path, 0u);
    PathPdf pdf = path_pdf_start();
    double log_q = 0.0;
    float3 normal = make_float3(0.0f, 0.0f, 1.0f), wo = make_float3(0.0f, 0.0f, 1.0f);
    int steps = 0;
    for (; steps < 500; ++steps) {
      const float u_lobe = rng_uniform(&rng), u1 = rng_uniform(&rng), u2 = rng_uniform(&rng);
      BsdfSample sample = bsdf_sample(&bsdf, normal, wo, u_lobe, u1, u2);
      ASSERT_TRUE(std::isfinite(sample.pdf_uv)) << "path " << path << " step " << steps;
      if (sample.pdf_uv <= 0.0f) break;  // below the surface: the kernel ends the path here too
      path_pdf_step(&pdf, bsdf.continuation, sample.pdf_uv);
      log_q += std::log(double(bsdf.continuation)) + std::log(double(sample.pdf_uv));
      ASSERT_TRUE(std::isfinite(pdf.log_q) && std::isfinite(pdf.log_r)) << "path " << path << " step " << steps;
      ASSERT_NEAR(pdf.log_q, log_q, 1e-4 * std::max(1.0, std::fabs(log_q)));
      // The other mirror, facing this one: its vertex sees the path arrive from here.
      wo = -sample.wi;
      normal = -normal;
    }
    EXPECT_GT(steps, 100) << "path " << path << " left the lobe early";
    EXPECT_GT(pdf.log_q, 100.0f) << "q should be far beyond float range (ln FLT_MAX = 88.7)";
    const float w = pt_emission_weight(&pdf, BP_WEIGHTS_PAPER, 1.0f);
    EXPECT_TRUE(std::isfinite(w) && w >= 0.0f && w <= 1.0f);
  }
}

}  // namespace
}  // namespace bp::test

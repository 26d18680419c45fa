// Refracting glass (KHR_materials_transmission with KHR_materials_volume; docs/design.md §11) on the test
// device: PT refracts by Snell's law with the exact Fresnel equations and attenuates inside by
// Beer-Lambert (closed forms: a clear closed object in a uniform sky is invisible, a slab passes
// (1 - F)^2 tint^2 a / (1 - F^2 a^2)); every refraction and reflection is a delta vertex, PT's alone,
// and RB sees the glass as opaque, so the combination with a glass block agrees with the path tracer.
#include "kernel/device_fixture.h"
#include "kernel/power_test.h"
#include "kernels/shared/dielectric.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

SceneMaterial glass(const glm::vec3& tint, const glm::vec3& attenuation, float ior = 1.5f) {
  SceneMaterial m;
  m.kd = glm::vec3(0.0f);  // all transmitter, no opaque rest
  m.transmission = 1.0f;
  m.transmission_tint = tint;
  m.ior = ior;
  m.volume = true;
  m.attenuation = attenuation;
  return m;
}

// The 12 triangles of the box [lo, hi] with outward normals (counter-clockwise seen from outside).
void add_cuboid(Scene& scene, const glm::vec3& lo, const glm::vec3& hi, std::uint32_t material) {
  const glm::vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                          {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  const int faces[6][4] = {{3, 2, 1, 0}, {6, 7, 4, 5}, {7, 3, 0, 4}, {2, 6, 5, 1}, {0, 1, 5, 4}, {7, 6, 2, 3}};
  for (const auto& f : faces) {
    scene.triangles.push_back({{c[f[0]], c[f[1]], c[f[2]]}, material});
    scene.triangles.push_back({{c[f[0]], c[f[2]], c[f[3]]}, material});
  }
  for (const glm::vec3& q : c) scene.bounds.grow(q);
}

// A clear, colourless glass cube under a uniform sky, seen obliquely: every path that enters leaves
// again, so a closed dielectric without absorption is invisible in a furnace -- each path's
// throughput is 1 exactly (refraction's (n_i / n_t)^2 in and out, Fresnel's choice over its
// probability), whatever the number of internal reflections. So every pixel is the sky, to rounding.
TEST(RefractionRender, AClearGlassCubeIsInvisibleInAUniformSky) {
  Scene scene;
  scene.materials = {glass(glm::vec3(1.0f), glm::vec3(0.0f))};
  add_cuboid(scene, glm::vec3(-0.5f), glm::vec3(0.5f), 0);
  scene.environment = glm::vec3(1.5f);
  scene.camera.position = glm::vec3(1.6f, 1.2f, 2.0f);
  scene.camera.forward = glm::normalize(-scene.camera.position);
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 0.7f;  // the cube fills most of the view
  const ImageRGB img = render_pt(scene, 24, 24, 16, 3, 4096, false).image;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(img.pixel(x, y)[c], 1.5f, 1e-3f) << "pixel " << x << "," << y;
}

// From inside the same cube the sky is n^2 = 2.25 times brighter: L / n^2 is what is invariant along
// a ray across an interface, and a closed clear medium in a uniform sky is in equilibrium with it.
// The camera at the centre looks at a face through a narrow view (0.3 rad): every path leaves
// through the two faces across the view's axis, at under 0.15 rad, after any number of internal
// reflections (the side faces reflect it totally), so each carries exactly n^2 L. The outside view
// above cannot see this factor (it enters and leaves, and cancels).
TEST(RefractionRender, FromInsideAClearGlassCubeTheSkyIsBrighterByTheSquareOfTheIndex) {
  Scene scene;
  scene.materials = {glass(glm::vec3(1.0f), glm::vec3(0.0f))};
  add_cuboid(scene, glm::vec3(-0.5f), glm::vec3(0.5f), 0);
  scene.environment = glm::vec3(1.5f);
  scene.camera.position = glm::vec3(0.0f);
  scene.camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.yfov = 0.3f;
  const ImageRGB img = render_pt(scene, 16, 16, 16, 5, 4096, false).image;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(img.pixel(x, y)[c], 1.5f * 2.25f, 2e-3f) << "pixel " << x << "," << y;
}

// Inside the cube, looking along a diagonal: every face meets the ray at 54.7 degrees, past the
// critical angle (41.8), so the ray is reflected totally forever. After 64 delta vertices in a row
// Russian roulette ends it (survival 0.9: about 10 more on average), rather than --max-depth's
// 65536 bounces; it carries nothing, since nothing inside the cube emits.
TEST(RefractionRender, APathTrappedByTotalInternalReflectionEndsByRoulette) {
  Scene scene;
  scene.materials = {glass(glm::vec3(1.0f), glm::vec3(0.0f))};
  add_cuboid(scene, glm::vec3(-0.5f), glm::vec3(0.5f), 0);
  scene.environment = glm::vec3(1.0f);
  scene.camera.position = glm::vec3(0.0f);
  scene.camera.forward = glm::normalize(glm::vec3(1.0f));
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 0.05f;
  const RenderRun run = render_pt(scene, 8, 8, 16, 7, 65536, false);
  const double rays_per_path = double(run.outcome.rays) / (8.0 * 8.0 * 16.0);
  EXPECT_GT(rays_per_path, 64.0);
  EXPECT_LT(rays_per_path, 100.0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) ASSERT_EQ(run.image.pixel(x, y)[0], 0.0f);
}

// Seen straight down through a 0.1 m slab, tinted and absorbing, above a black emitter: the light
// crosses two interfaces (1 - F0 each, tinted each time) and the medium (a = exp(-sigma d)), and
// bounces between the faces (F0^2 a^2 per round trip): (1 - F0)^2 tint^2 a / (1 - F0^2 a^2) of Le.
// A narrow view (0.02 rad) keeps every ray within 0.01 rad of normal incidence, where F differs from
// F0 = 0.04 by under 1e-5. Mean of independent runs against the closed form, z-test.
TEST(RefractionRender, ASlabPassesTwoInterfacesAndItsMediumsAttenuation) {
  const glm::vec3 le(2.0f, 3.0f, 4.0f), tint(1.0f, 0.8f, 0.9f);
  const float thickness = 0.1f;
  const glm::vec3 sigma(std::log(2.0f) / thickness, 0.0f, std::log(4.0f) / thickness);  // a = 1/2, 1, 1/4
  Scene scene;
  SceneMaterial lamp;
  lamp.kd = glm::vec3(0.0f);
  lamp.emission = le;
  scene.materials = {lamp, glass(tint, sigma)};
  const float h = 50.0f;  // the emitter at y = 0 facing +y: counter-clockwise seen from +y
  scene.triangles.push_back({{{-h, 0, -h}, {-h, 0, h}, {h, 0, h}}, 0});
  scene.triangles.push_back({{{-h, 0, -h}, {h, 0, h}, {h, 0, -h}}, 0});
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& q : t.p) scene.bounds.grow(q);
  add_cuboid(scene, glm::vec3(-h, 0.4f, -h), glm::vec3(h, 0.4f + thickness, h), 1);
  scene.camera.position = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.yfov = 0.02f;
  const int runs = 16;
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int k = 0; k < runs; ++k) {
    const ImageRGB img = render_pt(scene, 16, 16, 32, 200 + 11 * k).image;
    for (int c = 0; c < 3; ++c) {
      double m = 0.0;
      for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) m += img.pixel(x, y)[c] / 256.0;
      sum[c] += m;
      sum2[c] += m * m;
    }
  }
  const double f0 = dielectric_fresnel(1.5f, 1.0f);
  for (int c = 0; c < 3; ++c) {
    const double a = std::exp(-double(sigma[c]) * thickness);
    const double expected = le[c] * (1.0 - f0) * (1.0 - f0) * tint[c] * tint[c] * a / (1.0 - f0 * f0 * a * a);
    const double mean = sum[c] / runs, se = std::sqrt(std::max(0.0, sum2[c] / runs - mean * mean) / (runs - 1));
    ASSERT_LT(se, 0.005 * expected) << "too few samples to see a 2 % error, channel " << c;
    EXPECT_LT(std::fabs(mean - expected), 4.0 * se + 1e-4 * expected)
        << "channel " << c << ": " << mean << " vs " << expected << " (se " << se << ")";
  }
}

// The glossy light box with a tinted, absorbing glass block on its floor below the lamp, in view:
// the floor under the block is lit through it (PT's walk alone, refraction being a delta), the
// eye sees the room refracted through it (PT's alone) and the block's opaque rest (both).
Scene box_with_a_glass_block() {
  Scene scene = make_glossy_light_box();
  const std::uint32_t m = std::uint32_t(scene.materials.size());
  SceneMaterial block = glass(glm::vec3(0.95f, 0.9f, 0.8f), glm::vec3(0.5f, 1.0f, 2.0f));
  block.transmission = 0.8f;  // and an opaque rest of 0.2 x kd 0.5 (scaled at load, as the loader does)
  block.kd = glm::vec3(0.1f);
  scene.materials.push_back(block);
  add_cuboid(scene, glm::vec3(-0.2f, -0.5f, -0.25f), glm::vec3(0.15f, -0.1f, 0.1f), m);
  return scene;
}

// With the power to see a 2 % bias (power_test.h): a refraction given a share to RB, which
// cannot carry it, darkens the block and what is seen through it.
TEST(RefractionRender, TheCombinationWithAGlassBlockMatchesThePathTracerWithThePowerToSeeTwoPercent) {
  expect_combination_matches_pt_with_power_to_see_two_percent(box_with_a_glass_block(), "box with a glass block");
}

}  // namespace
}  // namespace bp::test

// glTF's metallic-roughness BRDF in both estimators (DESIGN.md §11): a GGX surface under a uniform
// environment reflects exactly its directional albedo -- PT alone, RB alone and combined, with and
// without light sampling -- and in a closed box with a rough gold floor and plastic walls the product
// combination converges to the path tracer's answer, with the power to see a 2 % bias.
#include "device/device_scene.h"
#include "kernel/device_fixture.h"
#include "kernel/region_test.h"
#include "stats.h"

#include "kernels/shared/brdf.h"
#include "kernels/shared/camera.h"

#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace bp::test {
namespace {

SceneMaterial ggx_material(glm::vec3 base, float metallic, float roughness) {
  SceneMaterial m;
  m.ggx = true;
  m.kd = glm::vec3(0.0f);
  m.base_color = base;
  m.metallic = metallic;
  m.roughness = roughness;
  m.dielectric_f0 = glm::vec3(0.04f);
  m.specular_weight = 1.0f;
  return m;
}

// ---------------------------------------------------------------- the white furnace of a convex surface

// A 20 m square facing +y, seen obliquely (about 40 to 65 degrees from its normal) so that every pixel
// sees it, under a uniform environment of radiance 1: a convex surface sees the environment alone, so
// a pixel reads the directional albedo E(wo) = integral of f cos over wi, with no discretisation for
// RB to blame (every patch receives the same light from every direction).
constexpr int kFurnaceSize = 16;

Scene make_environment_plane(const SceneMaterial& m) {
  Scene scene;
  scene.materials = {m};
  const float h = 10.0f;
  scene.triangles.push_back({{{-h, 0, -h}, {-h, 0, h}, {h, 0, h}}, 0});  // counter-clockwise seen from +y
  scene.triangles.push_back({{{-h, 0, -h}, {h, 0, h}, {h, 0, -h}}, 0});
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  scene.environment = glm::vec3(1.0f);
  scene.camera.position = glm::vec3(0.0f, 1.0f, 1.5f);
  scene.camera.forward = glm::normalize(glm::vec3(0.0f, -1.0f, -1.2f));
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 0.5f;
  scene.camera.aspect = 1.0f;
  return scene;
}

// The exact image: per pixel, E(wo) of the ray through its centre, by quadrature of the shared f over
// half vectors (tan theta_h = alpha tan psi, so every alpha is resolved); tests/unit/test_ggx.cpp holds
// that f to the textbook GGX.
glm::dvec3 directional_albedo(const Material& material, float3 wo) {
  const Bsdf b = bsdf_from_material(&material);
  const float3 n = make_float3(0, 1, 0);
  const Frame frame = frame_from_normal(n);
  const double alpha = ggx_alpha_from_roughness(material.roughness);
  const int nt = 400, np = 400;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < nt; ++i) {
    const double psi = (i + 0.5) * 0.5 * M_PI / nt, t = std::tan(psi), theta_h = std::atan(alpha * t);
    const double jac = alpha / (std::cos(psi) * std::cos(psi) * (1.0 + alpha * alpha * t * t));
    for (int j = 0; j < np; ++j) {
      const double phi = (j + 0.5) * 2 * M_PI / np;
      const float3 h = frame_to_world(&frame, make_float3(float(std::sin(theta_h) * std::cos(phi)),
                                                          float(std::sin(theta_h) * std::sin(phi)),
                                                          float(std::cos(theta_h))));
      const float wo_h = dot(wo, h);
      if (wo_h <= 0.0f) continue;
      const float3 wi = reflect_about(wo, h);
      const float cos_i = dot(n, wi);
      if (cos_i <= 0.0f) continue;
      const float3 f = bsdf_eval(&b, n, wi, wo);
      sum += glm::dvec3(f.x, f.y, f.z) * (cos_i * 4.0 * wo_h * std::sin(theta_h) * jac * (0.5 * M_PI / nt) * (2 * M_PI / np));
    }
  }
  return sum;
}

// The large regions (channel means) of the exact image.
std::vector<double> exact_regions(const Scene& scene) {
  const std::vector<Material> materials = pack_materials(scene, LightList{});  // as the device gets them
  // E depends on the angle of wo alone (an isotropic BRDF): a table over the image's angles, linear
  // between its 65 entries (the interpolation error is far below the quadrature's)
  const CameraParams camera = pack_camera(scene.camera, kFurnaceSize, kFurnaceSize);
  std::vector<float3> wo(kFurnaceSize * kFurnaceSize);
  double lo = M_PI, hi = 0.0;
  for (int y = 0; y < kFurnaceSize; ++y)
    for (int x = 0; x < kFurnaceSize; ++x) {
      const float3 d = camera_ray_direction(&camera, std::uint32_t(x), std::uint32_t(y), 0.5f, 0.5f);
      EXPECT_LT(d.y, 0.0f) << "the plane must fill the view";
      wo[y * kFurnaceSize + x] = -d;
      lo = std::min(lo, std::acos(double(-d.y)));
      hi = std::max(hi, std::acos(double(-d.y)));
    }
  const int entries = 65;
  std::vector<glm::dvec3> table(entries);
  for (int k = 0; k < entries; ++k) {
    const double theta = lo + (hi - lo) * k / (entries - 1);
    table[k] = directional_albedo(materials[0], make_float3(float(std::sin(theta)), float(std::cos(theta)), 0.0f));
  }
  ImageRGB exact(kFurnaceSize, kFurnaceSize);
  for (int p = 0; p < kFurnaceSize * kFurnaceSize; ++p) {
    const double u = (std::acos(double(wo[p].y)) - lo) / (hi - lo) * (entries - 1);
    const int k = std::min(entries - 2, int(u));
    const glm::dvec3 e = table[k] + (table[k + 1] - table[k]) * (u - k);
    for (int c = 0; c < 3; ++c) exact.pixel(p % kFurnaceSize, p / kFurnaceSize)[c] = float(e[c]);
  }
  return large_region_means(exact);
}

struct FurnaceCase {
  std::string name;
  int pt_samples, rb_iterations;  // per round; 0 PT samples: RB alone, 0 RB iterations: PT alone
  std::uint64_t rounds;
  bool light_sampling, eye_direct_shared;
};

ImageRGB furnace_render(const Scene& scene, const FurnaceCase& fc, std::uint32_t seed) {
  if (fc.rb_iterations == 0)
    return render_pt(scene, kFurnaceSize, kFurnaceSize, fc.rounds * fc.pt_samples, seed, 65536, fc.light_sampling).image;
  CombinedSettings cs;
  cs.weight_mode = BP_WEIGHTS_PRODUCT;
  cs.pt_samples_per_round = fc.pt_samples;
  cs.rb_iterations_per_round = fc.rb_iterations;
  cs.rounds = fc.rounds;
  cs.light_sampling = fc.light_sampling;
  cs.eye_direct_shared = fc.eye_direct_shared;
  cs.patch_size = 2.0f;
  cs.warmup = 0;  // nothing reflects into the plane: its radiance is exact from the first iteration
  cs.seed = seed;
  return render_combined(scene, kFurnaceSize, kFurnaceSize, cs).combined;
}

void expect_furnace_exact(const SceneMaterial& material, const char* what) {
  const Scene scene = make_environment_plane(material);
  const std::vector<double> exact = exact_regions(scene);
  const std::vector<FurnaceCase> cases = {
      {"PT alone", 1, 0, 64, false, false},
      {"PT alone, light sampling", 1, 0, 32, true, false},
      {"RB alone", 0, 16, 384, false, false},  // one direction per iteration for every pixel: many iterations
      {"combined N2/N1 4", 1, 4, 768, false, false},
      {"combined N2/N1 4, light sampling, eye shared", 1, 4, 32, true, true},
  };
  const int runs = 16;
  const double alpha = sidak_alpha(0.01, int(cases.size()) * kLargeRegions);
  for (const FurnaceCase& fc : cases) {
    const RegionRuns r = large_region_runs(runs, 501, [&](std::uint32_t seed) { return furnace_render(scene, fc, seed); });
    std::printf("[ggx furnace %s] %-46s mean %.5f (exact %.5f, %+.2f %%)  rel. se %.3f %%\n", what, fc.name.c_str(),
                r.mean[0], exact[0], 100.0 * (r.mean[0] / exact[0] - 1.0), 100.0 * r.se[0] / exact[0]);
    EXPECT_LT(r.se[0] / exact[0], 0.005) << fc.name << ": too noisy to see a 2 % bias";
    for (int i = 0; i < kLargeRegions; ++i) {
      const double t = (r.mean[i] - exact[i]) / r.se[i];
      EXPECT_GT(student_t_two_sided_p(t, runs - 1), alpha)
          << what << ", " << fc.name << ", " << large_region_name(i) << ": " << r.mean[i] << " vs exact " << exact[i]
          << " (t " << t << ")";
    }
  }
}

TEST(GgxFurnace, RoughWhiteMetalReflectsItsDirectionalAlbedoInBothEstimators) {
  // F0 = 1: the image is GGX's single-scattering albedo, about 0.9 here
  expect_furnace_exact(ggx_material(glm::vec3(1.0f), 1.0f, 0.5f), "white metal r0.5");
}

TEST(GgxFurnace, GlossyPlasticReflectsItsDirectionalAlbedoInBothEstimators) {
  // both lobes, chosen per direction by the Fresnel-aware estimate; Fresnel grows towards grazing
  expect_furnace_exact(ggx_material(glm::vec3(0.7f, 0.3f, 0.1f), 0.0f, 0.2f), "plastic r0.2");
}

// ---------------------------------------------------------------- the combination in a closed box

// The glossy light box (device_fixture.h) with glTF materials: a rough gold floor (roughness 0.2), a
// red plastic back wall (0.5), a half-metallic left wall (0.35), the other walls Lambert.
Scene make_ggx_light_box() {
  Scene scene = make_glossy_light_box();
  scene.materials[1] = ggx_material(glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, 0.2f);  // the floor
  scene.materials.push_back(ggx_material(glm::vec3(0.6f, 0.08f, 0.05f), 0.0f, 0.5f));
  scene.materials.push_back(ggx_material(glm::vec3(0.5f, 0.5f, 0.55f), 0.5f, 0.35f));
  const std::uint32_t plastic = std::uint32_t(scene.materials.size() - 2), half_metal = plastic + 1;
  for (SceneTriangle& t : scene.triangles) {
    if (t.p[0].z == -0.5f && t.p[1].z == -0.5f && t.p[2].z == -0.5f) t.material = plastic;
    if (t.p[0].x == -0.5f && t.p[1].x == -0.5f && t.p[2].x == -0.5f) t.material = half_metal;
  }
  return scene;
}

// Images of `runs` independent renders as 8x8-block samples and as large regions.
struct Runs {
  Sample blocks;
  RegionRuns regions;
};
template <class Render>
Runs collect_runs(int runs, Render render) {
  std::vector<ImageRGB> images;
  for (int k = 0; k < runs; ++k) images.push_back(render(std::uint32_t(1000 + 37 * k)));
  std::size_t next = 0;
  Runs out;
  out.blocks = independent_runs(runs, [&](std::uint32_t) { return images[next++]; });
  next = 0;
  out.regions = large_region_runs(runs, 0, [&](std::uint32_t) { return images[next++]; });
  return out;
}

void expect_combination_matches_pt(bool light_sampling, bool eye_shared) {
  const Scene scene = make_ggx_light_box();
  const int runs = 12;
  const Runs reference = collect_runs(runs, [&](std::uint32_t seed) {
    return render_pt(scene, kSize, kSize, 512, seed, 65536, light_sampling).image;
  });
  const Runs combined = collect_runs(runs, [&](std::uint32_t seed) {
    CombinedSettings cs;
    cs.weight_mode = BP_WEIGHTS_PRODUCT;
    cs.light_sampling = light_sampling;
    cs.eye_direct_shared = eye_shared;
    cs.rounds = 96;  // 96 spp + 384 iterations
    cs.patch_size = 0.05f;
    cs.seed = seed + 1;
    return render_combined(scene, kSize, kSize, cs).combined;
  });
  const std::string what = std::string(light_sampling ? "light sampling" : "no light sampling") +
                           (eye_shared ? ", eye shared" : "");
  for (const std::string& d : significant_differences(combined.blocks, reference.blocks, runs))
    ADD_FAILURE() << what << ", " << d;
  // The image mean and its quadrants, with the power to see 2 %.
  const double alpha = sidak_alpha(0.01, kLargeRegions);
  for (int i = 0; i < kLargeRegions; ++i) {
    const WelchT w = welch_t(combined.regions, reference.regions, i);
    if (i == 0) {
      // (without light sampling the small light is found by BSDF sampling alone: PT's own noise is
      // several times larger, and only the blocks' t-tests above are asked of it)
      std::printf("[ggx box, %s] combined %.5f, PT %.5f (%+.2f %%), se of the difference %.3f %%\n", what.c_str(),
                  combined.regions.mean[0], reference.regions.mean[0],
                  100.0 * (combined.regions.mean[0] / reference.regions.mean[0] - 1.0),
                  100.0 * w.se / reference.regions.mean[0]);
      if (light_sampling) {
        EXPECT_LT(w.se / reference.regions.mean[0], 0.005) << what << ": too noisy to see a 2 % bias";
      }
    }
    EXPECT_GT(student_t_two_sided_p(w.t, w.dof), alpha)
        << what << ", " << large_region_name(i) << ": combined " << combined.regions.mean[i] << " vs PT "
        << reference.regions.mean[i] << " (t " << w.t << ")";
  }
}

TEST(GgxCombination, ProductWeightsConvergeToThePathTracedReference) { expect_combination_matches_pt(false, false); }

TEST(GgxCombination, ProductWeightsWithLightSamplingConvergeToThePathTracedReference) {
  expect_combination_matches_pt(true, true);
}

}  // namespace
}  // namespace bp::test

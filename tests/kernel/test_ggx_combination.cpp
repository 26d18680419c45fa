// glTF's metallic-roughness BRDF in both estimators (docs/design.md §11): a GGX surface under a uniform
// environment reflects exactly its directional albedo -- PT alone, RB alone and combined, with and
// without light sampling -- and in a closed box with a rough gold floor and plastic walls the product
// combination converges to the path tracer's answer, with the power to see a 2 % bias, also with
// KHR_materials_specular's textures finer than the patches.
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

// The large regions (channel means) of the exact image. `texel_materials`: where given, the plane's
// f is the first left of x = 0 and the second right of it (a texture's two halves), else the scene's.
std::vector<double> exact_regions(const Scene& scene, const std::vector<Material>& texel_materials = {}) {
  const std::vector<Material> materials =
      texel_materials.empty() ? pack_materials(scene, LightList{}) : texel_materials;  // as the device gets them
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
  const std::size_t kinds = texel_materials.empty() ? 1 : 2;
  std::vector<std::vector<glm::dvec3>> tables(kinds, std::vector<glm::dvec3>(entries));
  for (std::size_t m = 0; m < kinds; ++m)
    for (int k = 0; k < entries; ++k) {
      const double theta = lo + (hi - lo) * k / (entries - 1);
      tables[m][k] = directional_albedo(materials[m], make_float3(float(std::sin(theta)), float(std::cos(theta)), 0.0f));
    }
  ImageRGB exact(kFurnaceSize, kFurnaceSize);
  for (int p = 0; p < kFurnaceSize * kFurnaceSize; ++p) {
    const double u = (std::acos(double(wo[p].y)) - lo) / (hi - lo) * (entries - 1);
    const int k = std::min(entries - 2, int(u));
    // the camera is above x = 0: a pixel's ray reaches the plane left of it where it points left
    const std::vector<glm::dvec3>& table = tables[kinds == 2 && -wo[p].x > 0.0f ? 1 : 0];
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

void expect_furnace_exact(const Scene& scene, const std::vector<double>& exact, const char* what) {
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

void expect_furnace_exact(const SceneMaterial& material, const char* what) {
  const Scene scene = make_environment_plane(material);
  expect_furnace_exact(scene, exact_regions(scene), what);
}

TEST(GgxFurnace, RoughWhiteMetalReflectsItsDirectionalAlbedoInBothEstimators) {
  // F0 = 1: the image is GGX's single-scattering albedo, about 0.9 here
  expect_furnace_exact(ggx_material(glm::vec3(1.0f), 1.0f, 0.5f), "white metal r0.5");
}

TEST(GgxFurnace, GlossyPlasticReflectsItsDirectionalAlbedoInBothEstimators) {
  // both lobes, chosen per direction by the Fresnel-aware estimate; Fresnel grows towards grazing
  expect_furnace_exact(ggx_material(glm::vec3(0.7f, 0.3f, 0.1f), 0.0f, 0.2f), "plastic r0.2");
}

// Textures: a 2 x 1 texture (NEAREST) whose texels the plane's halves x < 0 and x > 0 read as base
// colour and as KHR_materials_specular's specular and colour, one patch across the view (2 m
// patches). Each half reflects its own texel's albedo in every estimator: the path tracer's hits and
// RB's eye gather read the texel, not the patch's mean (which the weights read); and with the eye
// vertex's direct light shared, RB's Gouraud corners mix neighbouring patches' weights, which must be
// the pixel's own (the material's proxy, eye_direct_material_proxy_pdf_uv).
TEST(GgxFurnace, TexturedHalvesReflectTheirOwnTexelsAlbedoInBothEstimators) {
  SceneMaterial m = ggx_material(glm::vec3(0.6f), 0.0f, 0.5f);
  const std::uint32_t rgba[2] = {0xff2880ffu, 0x33c8ff3cu};  // (255, 128, 40, 255) and (60, 255, 200, 51)
  Scene scene = make_environment_plane(m);
  scene.texels = {rgba[0], rgba[1]};
  for (int srgb = 0; srgb < 2; ++srgb) {  // a linear view (specular: A) and an sRGB one (the colours)
    TextureView v{};
    v.width = 2;
    v.height = 1;
    v.flags = BP_WRAP_CLAMP_TO_EDGE | BP_WRAP_CLAMP_TO_EDGE << BP_TEXTURE_WRAP_T_SHIFT | BP_TEXTURE_NEAREST |
              (srgb ? BP_TEXTURE_SRGB : 0u);
    v.transform[0] = v.transform[3] = 1.0f;
    scene.texture_views.push_back(v);
  }
  scene.uv_slots = 1;
  MaterialTextures& t = scene.materials[0].textures;
  t.specular = 0;        // A, linear
  t.specular_color = 1;  // RGB, sRGB
  t.base_color = 1;
  t.specular_factor = 1.0f;
  for (int c = 0; c < 3; ++c) {
    t.specular_f0[c] = 0.04f * 15.0f;  // specularColorFactor 15
    t.base_color_factor[c] = m.base_color[c];
  }
  t.metallic_factor = m.metallic;
  t.roughness_factor = m.roughness;
  for (SceneTriangle& tri : scene.triangles)
    for (int k = 0; k < 3; ++k) tri.uv[0][k] = glm::vec2(tri.p[k].x > 0.0f ? 1.0f : 0.0f, 0.5f);
  // each half's f, from its texel as glTF defines it: base colour = factor sRGB(rgb), specular = A,
  // f0 = min(f0(ior) 15 sRGB(rgb), 1)
  std::vector<Material> halves(2, pack_materials(scene, LightList{})[0]);
  for (int h = 0; h < 2; ++h) {
    const std::uint32_t texel = rgba[h];
    halves[h].specular_weight = float(texel >> 24) / 255.0f;
    for (int c = 0; c < 3; ++c) {
      const float colour = srgb_to_linear(float(texel >> (8 * c) & 0xffu) / 255.0f);
      halves[h].base_color[c] = m.base_color[c] * colour;
      halves[h].dielectric_f0[c] = std::min(1.0f, 0.6f * colour);
    }
  }
  const std::vector<double> exact = exact_regions(scene, halves);
  ASSERT_GT(std::fabs(exact[1] / exact[2] - 1.0), 0.05) << "the halves must differ enough to see";
  expect_furnace_exact(scene, exact, "textured r0.5");
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

// The same box with KHR_materials_specular's textures on the plastic back wall: a 32 x 32 checker of
// specular (alpha 1 or 0.12) and colour, its cells 3 cm across, finer than the 5 cm patches, so f's
// Fresnel changes within a patch while every weight input reads the patch's mean (textured.h).
Scene make_specular_textured_box() {
  Scene scene = make_ggx_light_box();
  const std::uint32_t plastic = std::uint32_t(scene.materials.size() - 2);
  const int side = 32;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
      scene.texels.push_back((i + j) % 2 ? 0xffc83cffu : 0x1e5aff28u);  // ABGR: (255, 60, 200, 255), (40, 255, 90, 30)
  for (int srgb = 0; srgb < 2; ++srgb) {
    TextureView v{};
    v.width = v.height = side;
    v.flags = BP_WRAP_REPEAT | BP_WRAP_REPEAT << BP_TEXTURE_WRAP_T_SHIFT | (srgb ? BP_TEXTURE_SRGB : 0u);
    v.transform[0] = v.transform[3] = 1.0f;
    scene.texture_views.push_back(v);
  }
  scene.uv_slots = 1;
  SceneMaterial& m = scene.materials[plastic];
  MaterialTextures& t = m.textures;
  t.specular = 0;        // A: specular
  t.specular_color = 1;  // RGB (sRGB): its colour
  t.specular_factor = 1.0f;
  for (int c = 0; c < 3; ++c) {
    t.specular_f0[c] = 0.04f * 20.0f;  // specularColorFactor 20: f0 up to 0.8
    t.base_color_factor[c] = m.base_color[c];
  }
  t.metallic_factor = m.metallic;
  t.roughness_factor = m.roughness;
  for (SceneTriangle& tri : scene.triangles)
    for (int k = 0; k < 3; ++k) tri.uv[0][k] = glm::vec2(tri.p[k].x + 0.5f, 0.5f - tri.p[k].y);
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

void expect_combination_matches_pt(const Scene& scene, bool light_sampling, bool eye_shared) {
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

TEST(GgxCombination, ProductWeightsConvergeToThePathTracedReference) {
  expect_combination_matches_pt(make_ggx_light_box(), false, false);
}

TEST(GgxCombination, ProductWeightsWithLightSamplingConvergeToThePathTracedReference) {
  expect_combination_matches_pt(make_ggx_light_box(), true, true);
}

TEST(GgxCombination, SpecularTexturesUnderTheProductWeightsConvergeToThePathTracedReference) {
  const Scene scene = make_specular_textured_box();
  ASSERT_TRUE(scene.materials[scene.materials.size() - 2].textured());
  expect_combination_matches_pt(scene, true, true);
}

}  // namespace
}  // namespace bp::test

// The combination's invariant (docs/design.md §3): for any path, the weight the PT kernel code gives it and
// the weight the RB kernel code gives it sum to one (--weights product, and the paper's weights on a
// single path), never NaN, never outside [0, 1] -- run on the test device.
#include "environment_maps.h"
#include "kernel/device_fixture.h"

#include "device/launcher.h"
#include "device/program_cache.h"
#include "kernels/shared/brdf.h"
#include "kernels/shared/path_pdf.h"
#include "kernels/shared/lights.h"
#include "kernels/shared/weights.h"
#include "scene/lights.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp::test {
namespace {

struct Paths {
  std::vector<Material> materials;
  std::vector<float> geometry;  // n, wo, wi per vertex
};

float3 random_unit(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0, 1);
  float z = 1 - 2 * u(rng), s = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 6.2831853f * u(rng);
  return make_float3(s * std::cos(phi), s * std::sin(phi), z);
}

// Random vertices: albedo up to 0.999, shininess up to 1e4, wi mostly sampled from the BSDF itself (so
// sharp lobes give pdfs near 1e4), sometimes uniform, sometimes nearly grazing.
Paths make_paths(std::uint32_t paths, std::uint32_t vertices, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  const float shininess[] = {0.0f, 1.0f, 10.0f, 50.0f, 1000.0f, 1.0e4f};
  Paths p;
  for (std::uint32_t i = 0; i < paths * vertices; ++i) {
    Material m{};
    float albedo = u(rng) < 0.3f ? 0.999f : u(rng), split = u(rng);
    for (int c = 0; c < 3; ++c) {
      m.kd[c] = albedo * split;
      m.ks[c] = albedo * (1 - split);
    }
    m.shininess = shininess[std::size_t(u(rng) * 6) % 6];
    p.materials.push_back(m);
    Bsdf b = bsdf_from_material(&m);
    float3 n = random_unit(rng), wo;
    do wo = random_unit(rng); while (dot(wo, n) <= 0.05f);
    float3 wi;
    float pick = u(rng);
    if (pick < 0.7f) {
      BsdfSample s;
      do s = bsdf_sample(&b, n, wo, u(rng), u(rng), u(rng)); while (s.pdf_uv <= 0.0f);
      wi = s.wi;
    } else if (pick < 0.9f) {
      do wi = random_unit(rng); while (dot(wi, n) <= 0.0f);
    } else {
      wi = normalize(random_unit(rng) * 0.01f + normalize(cross(n, random_unit(rng))) + n * 1e-3f);
      if (dot(wi, n) <= 0.0f) wi = n;
    }
    for (float3 v : {n, wo, wi}) p.geometry.insert(p.geometry.end(), {v.x, v.y, v.z});
  }
  return p;
}

std::vector<float> run_weights(const Paths& paths, std::uint32_t count, std::uint32_t vertices, std::uint32_t mode,
                               float ratio, std::uint32_t heuristic) {
  const DeviceContext& device = test_device();
  BuiltProgram program = build_program(device, "test/weights_test.cl");
  cl::Kernel kernel(program.program, "path_weights");
  cl::Buffer materials = upload_buffer(device, "materials", paths.materials);
  cl::Buffer geometry = upload_buffer(device, "geometry", paths.geometry);
  cl::Buffer out = make_buffer(device, "weights", CL_MEM_WRITE_ONLY, 2 * count * sizeof(float));
  set_args(kernel, materials, geometry, vertices, count, mode, ratio, heuristic, out);
  Launcher launcher(device);
  launcher.launch("path_weights", kernel, count, 64);
  launcher.finish();
  std::vector<float> w(2 * count);
  device.queue.enqueueReadBuffer(out, CL_TRUE, 0, w.size() * sizeof(float), w.data());
  return w;
}

TEST(CombinationWeights, PtAndRbWeightsOfEveryPathSumToOne) {
  const std::uint32_t count = 2000;
  for (std::uint32_t vertices : {1u, 2u, 3u, 8u, 40u, 300u})
    for (float ratio : {1e-4f, 0.0625f, 1.0f, 16.0f, 1e4f}) {
      Paths paths = make_paths(count, vertices, 17u + vertices);
      for (std::uint32_t mode : {BP_WEIGHTS_PRODUCT, BP_WEIGHTS_PAPER, BP_WEIGHTS_NONE})
      for (std::uint32_t heuristic : {BP_BETA_CLAMPED, BP_BETA_BALANCE}) {
        if (mode != BP_WEIGHTS_PRODUCT && heuristic != BP_BETA_CLAMPED) continue;  // beta: product weights only
        std::vector<float> w = run_weights(paths, count, vertices, mode, ratio, heuristic);
        // Float products over the path: the tolerance grows with its length.
        const float tolerance = 2e-6f * float(vertices + 4);
        int bad = 0;
        for (std::uint32_t i = 0; i < count && bad < 5; ++i) {
          float w_pt = w[2 * i], w_rb = w[2 * i + 1];
          bool ok = std::isfinite(w_pt) && std::isfinite(w_rb) && w_pt >= 0.0f && w_pt <= 1.0f && w_rb >= 0.0f &&
                    w_rb <= 1.0f;
          if (mode != BP_WEIGHTS_NONE) ok = ok && std::fabs(w_pt + w_rb - 1.0f) <= tolerance;
          if (!ok) {
            ++bad;
            ADD_FAILURE() << "mode " << mode << ", beta " << heuristic << ", " << vertices << " vertices, N2/N1 " << ratio << ", path " << i
                          << ": w_PT " << w_pt << " + w_RB " << w_rb << " = " << w_pt + w_rb;
          }
        }
      }
    }
}

// Light-sampling densities of the last segment: tiny (a far, small light), ordinary, huge (a light
// seen at a grazing angle, capped at 1e30 by light_pdf_uv_area), zero (the light cannot be sampled
// from here), and delta lights (point and spot).
struct LightConnections {
  std::vector<float> pdf;
  std::vector<cl_uint> is_delta;
};
LightConnections make_light_connections(std::uint32_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  LightConnections c;
  for (std::uint32_t i = 0; i < count; ++i) {
    float pick = u(rng);
    // 2: a sun RB also samples on its own (--rb-sun own), its pdf the selection probability
    c.is_delta.push_back(pick < 0.1f ? 2u : pick < 0.2f ? 1u : 0u);
    c.pdf.push_back(pick < 0.1f ? u(rng) : pick < 0.3f ? 0.0f : pick < 0.4f ? 1e30f : std::pow(10.0f, -6.0f + 14.0f * u(rng)));
  }
  return c;
}

// docs/design.md §3, light sampling: for random paths of every length (1 = the eye vertex's direct light,
// which PT owns alone under --eye-direct pt and shares with RB under --eye-direct shared), area and delta lights, the four techniques' weights computed the way the PT
// kernel and the RB kernel compute them sum to one, each finite and in [0, 1].
template <class Connections>
void expect_four_techniques_sum_to_one(Connections make_connections) {
  const std::uint32_t count = 2000;
  const DeviceContext& device = test_device();
  BuiltProgram program = build_program(device, "test/weights_test.cl");
  cl::Kernel kernel(program.program, "last_segment_path_weights");
  for (cl_uint eye_shared : {0u, 1u})
  for (float light_rate : {1.0f, 0.1f})
  for (std::uint32_t heuristic : {BP_BETA_CLAMPED, BP_BETA_BALANCE})
  for (std::uint32_t vertices : {1u, 2u, 3u, 8u, 40u, 300u})
    for (float ratio : {1e-4f, 0.0625f, 1.0f, 16.0f, 1e4f}) {
      Paths paths = make_paths(count, vertices, 29u + vertices);
      LightConnections lights = make_connections(count, 31u + vertices);
      cl::Buffer materials = upload_buffer(device, "materials", paths.materials);
      cl::Buffer geometry = upload_buffer(device, "geometry", paths.geometry);
      cl::Buffer pdf = upload_buffer(device, "light pdfs", lights.pdf);
      cl::Buffer delta = upload_buffer(device, "delta flags", lights.is_delta);
      cl::Buffer out = make_buffer(device, "weights", CL_MEM_WRITE_ONLY, 4 * count * sizeof(float));
      set_args(kernel, materials, geometry, pdf, delta, vertices, count, ratio, heuristic, light_rate, eye_shared, out);
      Launcher launcher(device);
      launcher.launch("last_segment_path_weights", kernel, count, 64);
      launcher.finish();
      std::vector<float> w(4 * count);
      device.queue.enqueueReadBuffer(out, CL_TRUE, 0, w.size() * sizeof(float), w.data());
      const float tolerance = 2e-6f * float(vertices + 4);
      int bad = 0;
      for (std::uint32_t i = 0; i < count && bad < 5; ++i) {
        float sum = 0.0f;
        bool ok = true;
        for (int k = 0; k < 4; ++k) {
          ok = ok && std::isfinite(w[4 * i + k]) && w[4 * i + k] >= 0.0f && w[4 * i + k] <= 1.0f;
          sum += w[4 * i + k];
        }
        if (vertices == 1 && !eye_shared) ok = ok && w[4 * i + 2] == 0.0f && w[4 * i + 3] == 0.0f;  // PT alone
        if (lights.is_delta[i]) ok = ok && w[4 * i] == 0.0f && w[4 * i + 2] == 0.0f;  // only light samples
        if (!ok || std::fabs(sum - 1.0f) > tolerance) {
          ++bad;
          ADD_FAILURE() << (eye_shared ? "eye direct shared, " : "") << "RB light rate " << light_rate << ", beta " << heuristic << ", " << vertices << " vertices, N2/N1 " << ratio << ", p_L " << lights.pdf[i]
                        << (lights.is_delta[i] ? " (delta)" : "") << ": PT bsdf " << w[4 * i] << " + PT light "
                        << w[4 * i + 1] << " + RB bundle " << w[4 * i + 2] << " + RB light " << w[4 * i + 3] << " = "
                        << sum;
        }
      }
    }
}

TEST(CombinationWeights, FourTechniquesOfTheLastSegmentSumToOne) {
  expect_four_techniques_sum_to_one(make_light_connections);
}

// The same where the light is the environment map (--environment FILE.exr): p_L of a direction is
// light_pdf_uv_environment's, the one function PT's BSDF samples, its light samples, RB's bundles and
// RB's light samples all call (kernels/shared/lights.h) -- over the graded sky with a sun beside it,
// from 0 (black texels, the poles) to huge (near the poles of a bright row).
LightConnections make_environment_connections(std::uint32_t count, std::uint32_t seed) {
  Scene scene;
  EnvironmentImage sky = graded_sky();
  for (int column = 0; column < 8; ++column)  // the top row: bright, with one black texel
    for (int c = 0; c < 3; ++c) sky.rgb[3 * column + c] = column == 2 ? 0.0f : 50.0f;
  scene.environment_image = std::make_shared<const EnvironmentImage>(sky);
  scene.bounds.grow(glm::vec3(-1.0f));
  scene.bounds.grow(glm::vec3(1.0f));
  ScenePunctualLight sun;
  sun.kind = ScenePunctualLight::Kind::directional;
  scene.lights = {sun};
  const LightList list = build_light_list(scene, build_bvh(scene.triangles));
  const std::vector<float> packed = pack_environment(sky);
  LightSet set = light_set(list.lights.data(), list.cdf.data(), nullptr, nullptr, std::uint32_t(list.lights.size()),
                           BP_LIGHT_SELECTION_POWER);
  set.environment = environment_map(packed.data(), 8u, 4u);
  std::mt19937 rng(seed);
  LightConnections c;
  for (std::uint32_t i = 0; i < count; ++i) {
    float3 wi = random_unit(rng);
    if (i % 7 == 0) wi = normalize(make_float3(wi.x * 1e-4f, 1.0f, wi.z * 1e-4f));  // at the pole
    c.pdf.push_back(light_pdf_uv_environment(&set, 0u, list.environment_light, wi));
    c.is_delta.push_back(0u);
  }
  return c;
}

TEST(CombinationWeights, FourTechniquesOfTheLastSegmentSumToOneForTheEnvironment) {
  expect_four_techniques_sum_to_one(make_environment_connections);
}

TEST(CombinationWeights, DirectlyVisibleEmitterBelongsToRbUnderProductWeights) {
  // The empty product: a path with no reflection has w_RB = 1, w_PT = 0 (docs/design.md §3).
  PathPdf p = path_pdf_start();
  EXPECT_EQ(pt_emission_weight(&p, BP_WEIGHTS_PRODUCT, 0.25f), 0.0f);
  // The paper's: the emitter seen directly is split N1 : N2.
  EXPECT_NEAR(pt_emission_weight(&p, BP_WEIGHTS_PAPER, 0.25f) + paper_rb_weight(0.0f, 0.25f), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace bp::test

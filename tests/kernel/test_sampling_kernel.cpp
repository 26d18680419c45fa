// Chi-square tests of the cosine, Phong-lobe and GGX (glTF metallic-roughness) samplers as they run
// in the kernel (on the test device), against the host-compiled pdf functions of kernels/shared/brdf.h.
#include "kernel/device_fixture.h"
#include "stats.h"

#include "device/launcher.h"
#include "device/program_cache.h"
#include "kernels/shared/brdf.h"

#include <gtest/gtest.h>
#include <cmath>

namespace bp::test {
namespace {

struct SamplerCase {
  const char* name;
  float kd, ks, shininess;
  float wo_theta;            // angle of wo from the normal
  float roughness = -1.0f;   // >= 0: glTF's metallic-roughness BRDF, base colour kd, F0 0.04
  float metallic = 0.0f;
  bool ggx() const { return roughness >= 0.0f; }
  bool lobe_only() const { return ggx() ? metallic == 1.0f : kd == 0.0f; }  // no diffuse lobe
};

// All cases of this file form one family (Šidák over them, alpha = 0.01).
const SamplerCase kCases[] = {
    {"cosine", 0.8f, 0.0f, 1.0f, 0.3f},      {"phong_n10_normal", 0.0f, 0.9f, 10.0f, 0.0f},
    {"phong_n50_oblique", 0.0f, 0.85f, 50.0f, 0.9f}, {"phong_n1000_grazing", 0.0f, 0.9f, 1000.0f, 1.45f},
    {"phong_n1e4", 0.0f, 0.9f, 1.0e4f, 0.6f},       {"mixture_n10", 0.45f, 0.45f, 10.0f, 0.7f},
    {"ggx_metal_r0_2", 0.9f, 0.0f, 0.0f, 0.6f, 0.2f, 1.0f}, {"ggx_metal_r0_6_grazing", 0.9f, 0.0f, 0.0f, 1.4f, 0.6f, 1.0f},
    {"ggx_plastic_r0_3", 0.6f, 0.0f, 0.0f, 1.1f, 0.3f, 0.0f}, {"ggx_half_metal_r0_5", 0.5f, 0.0f, 0.0f, 0.4f, 0.5f, 0.5f},
};
constexpr int kFamily = sizeof(kCases) / sizeof(kCases[0]);
constexpr std::uint32_t kSamples = 1u << 20;

struct Samples {
  std::vector<float> data;  // wi.xyz, pdf_uv
};

Samples run_sampler(const Material& material, float3 wo, std::uint32_t seed) {
  const DeviceContext& device = test_device();
  BuiltProgram program = build_program(device, "test/sampling_test.cl");
  cl::Kernel kernel(program.program, "sample_bsdf");
  cl::Buffer mat = make_buffer(device, "material", CL_MEM_READ_ONLY, sizeof(Material), &material);
  cl::Buffer out = make_buffer(device, "samples", CL_MEM_WRITE_ONLY, std::size_t(kSamples) * 4 * sizeof(float));
  set_args(kernel, mat, wo.x, wo.y, wo.z, seed, kSamples, out);
  Launcher launcher(device);
  launcher.launch("sample_bsdf", kernel, kSamples, 64);
  launcher.finish();
  Samples s;
  s.data.resize(std::size_t(kSamples) * 4);
  device.queue.enqueueReadBuffer(out, CL_TRUE, 0, s.data.size() * sizeof(float), s.data.data());
  return s;
}

Material make_material(const SamplerCase& c) {
  Material m{};
  if (c.ggx()) {
    m.flags = BP_MATERIAL_GGX;
    for (int i = 0; i < 3; ++i) { m.base_color[i] = c.kd; m.dielectric_f0[i] = 0.04f; }
    m.metallic = c.metallic;
    m.roughness = c.roughness;
    m.specular_weight = 1.0f;
    return m;
  }
  for (int i = 0; i < 3; ++i) { m.kd[i] = c.kd; m.ks[i] = c.ks; }
  m.shininess = c.shininess;
  return m;
}

// A Phong exponent of the same width as the case's lobe: the tests' cells and tolerances scale with it.
float lobe_shininess(const SamplerCase& c) {
  if (!c.ggx()) return c.shininess;
  const float alpha = ggx_alpha_from_roughness(c.roughness);
  return 2.0f / (alpha * alpha) - 2.0f;
}

class SamplerChiSquare : public ::testing::TestWithParam<SamplerCase> {};

TEST_P(SamplerChiSquare, KernelSamplesFollowThePdf) {
  const SamplerCase& c = GetParam();
  const Material material = make_material(c);
  Bsdf bsdf = bsdf_from_material(&material);
  const float3 n = make_float3(0, 0, 1);
  const float3 wo = make_float3(std::sin(c.wo_theta), 0.0f, std::cos(c.wo_theta));
  Samples s = run_sampler(material, wo, 7u);

  // Cells in a frame around the lobe axis: the normal for diffuse/mixture, the mirror direction for
  // a pure Phong lobe, with polar cells scaled to the lobe's width so sharp lobes are resolved.
  const bool lobe_only = c.lobe_only();
  const float3 axis = lobe_only ? reflect_about(wo, n) : n;
  Frame frame = frame_from_normal(axis);
  // GGX's tails are longer than Phong's: twice the range (what falls beyond is the last cell)
  const double width = (c.ggx() ? 12.0 : 6.0) * std::sqrt(2.0 / (lobe_shininess(c) + 2.0));
  const double theta_max = lobe_only ? std::min(M_PI, width + 0.05) : M_PI / 2;
  const int n_theta = 24, n_phi = 32;
  std::vector<double> observed(n_theta * n_phi + 1, 0.0), expected(n_theta * n_phi + 1, 0.0);
  const std::size_t rest = observed.size() - 1;  // beyond theta_max, or below the surface (pdf 0)

  for (std::uint32_t i = 0; i < kSamples; ++i) {
    const float* v = &s.data[4 * std::size_t(i)];
    if (v[3] <= 0.0f) { observed[rest] += 1; continue; }
    float3 w = make_float3(v[0], v[1], v[2]);
    double theta = std::acos(std::clamp<double>(dot(w, frame.n), -1.0, 1.0));
    double phi = std::atan2(double(dot(w, frame.b)), double(dot(w, frame.t)));
    if (phi < 0) phi += 2 * M_PI;
    if (theta >= theta_max) { observed[rest] += 1; continue; }
    int it = std::min(n_theta - 1, int(theta / theta_max * n_theta));
    int ip = std::min(n_phi - 1, int(phi / (2 * M_PI) * n_phi));
    observed[std::size_t(it) * n_phi + ip] += 1;
  }
  // Expected: the host pdf (solid angle = pdf_uv / 2pi) integrated over each cell, 12x12 midpoints.
  double total_inside = 0.0;
  for (int it = 0; it < n_theta; ++it)
    for (int ip = 0; ip < n_phi; ++ip) {
      double sum = 0.0;
      const int sub = 12;
      double dt = theta_max / n_theta / sub, dp = 2 * M_PI / n_phi / sub;
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
          double theta = (it * sub + a + 0.5) * dt, phi = (ip * sub + b + 0.5) * dp;
          float3 local = make_float3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                                     float(std::cos(theta)));
          float3 w = frame_to_world(&frame, local);
          sum += bsdf_pdf_uv(&bsdf, n, w, wo) / (2 * M_PI) * std::sin(theta) * dt * dp;
        }
      expected[std::size_t(it) * n_phi + ip] = sum * kSamples;
      total_inside += sum;
    }
  expected[rest] = std::max(0.0, 1.0 - total_inside) * kSamples;

  ChiSquareResult r = chi_square_test(observed, expected);
  EXPECT_GT(r.p_value, sidak_alpha(0.01, kFamily))
      << c.name << ": chi2 = " << r.statistic << " with " << r.dof << " dof, p = " << r.p_value;
}

TEST_P(SamplerChiSquare, ReturnedPdfEqualsHostPdfFunction) {
  const SamplerCase& c = GetParam();
  const Material material = make_material(c);
  Bsdf bsdf = bsdf_from_material(&material);
  const float3 n = make_float3(0, 0, 1);
  const float3 wo = make_float3(std::sin(c.wo_theta), 0.0f, std::cos(c.wo_theta));
  Samples s = run_sampler(material, wo, 11u);
  int checked = 0;
  for (std::uint32_t i = 0; i < kSamples; i += 97) {
    const float* v = &s.data[4 * std::size_t(i)];
    float host_pdf = bsdf_pdf_uv(&bsdf, n, make_float3(v[0], v[1], v[2]), wo);
    // Device and host may round differently (FMA contraction); cos^n alpha amplifies an ulp of
    // cos alpha by n, so the tolerance grows with the shininess.
    float tolerance = (2e-5f + 5e-7f * lobe_shininess(c)) * std::max(1.0f, host_pdf);
    ASSERT_NEAR(v[3], host_pdf, tolerance) << c.name << " sample " << i;
    ++checked;
  }
  EXPECT_GT(checked, 10000);
}

INSTANTIATE_TEST_SUITE_P(Kernel, SamplerChiSquare, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace bp::test

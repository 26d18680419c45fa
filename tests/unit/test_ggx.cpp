// glTF's metallic-roughness BRDF (kernels/shared/ggx.h, metallic_roughness.h) compiled as C++:
// against a textbook double-precision GGX written here (Walter et al. 2007; Heitz 2014), the
// normalisations of D and of the visible-normal density, the sampler by chi-square and by furnaces
// whose answers come from quadrature, reciprocity, and the loader-side invariants of s and the
// lobe choice.
#include "stats.h"

#include "kernels/shared/brdf.h"
#include "kernels/shared/rng.h"
#include "kernels/shared/textured.h"
#include "kernels/shared/weights.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp::test {
namespace {

const float3 kNormal = make_float3(0, 0, 1);

float3 dir_from_angles(double theta, double phi) {
  return make_float3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                     float(std::cos(theta)));
}

struct GgxMaterial {
  float base[3];
  float metallic, roughness, specular_weight;
  float dielectric_f0[3];
};

Material make_material(const GgxMaterial& g) {
  Material m{};
  m.flags = BP_MATERIAL_GGX;
  for (int c = 0; c < 3; ++c) {
    m.base_color[c] = g.base[c];
    m.dielectric_f0[c] = g.dielectric_f0[c];
  }
  m.metallic = g.metallic;
  m.roughness = g.roughness;
  m.specular_weight = g.specular_weight;
  return m;
}

// A conductor with F0 = 1 (white metal): f is GGX's specular_brdf alone.
GgxMaterial white_metal(float roughness) { return {{1, 1, 1}, 1.0f, roughness, 1.0f, {0.04f, 0.04f, 0.04f}}; }

// ---------------------------------------------------------------- the textbook GGX, in double

// D(h) = alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2)   (Walter et al. 2007, eq. 33)
double textbook_d(double alpha, double cos_h) {
  if (cos_h <= 0.0) return 0.0;
  const double c2 = cos_h * cos_h, tan2 = (1.0 - c2) / c2, a2 = alpha * alpha;
  return a2 / (M_PI * c2 * c2 * (a2 + tan2) * (a2 + tan2));
}

// Lambda(w) = (-1 + sqrt(1 + alpha^2 tan^2)) / 2   (Heitz 2014, eq. 86)
double textbook_lambda(double alpha, double cos_theta) {
  const double c2 = cos_theta * cos_theta, tan2 = (1.0 - c2) / c2;
  return 0.5 * (-1.0 + std::sqrt(1.0 + alpha * alpha * tan2));
}

// GGX's specular BRDF with glTF's alpha = roughness^2 and the height-correlated Smith
// G2 = 1 / (1 + Lambda(wi) + Lambda(wo)): D G2 / (4 cos_i cos_o)   (Heitz 2014, eq. 99)
double textbook_specular(double roughness, double cos_i, double cos_o, double cos_h) {
  if (cos_i <= 0.0 || cos_o <= 0.0) return 0.0;
  const double alpha = roughness * roughness;
  const double g2 = 1.0 / (1.0 + textbook_lambda(alpha, cos_i) + textbook_lambda(alpha, cos_o));
  return textbook_d(alpha, cos_h) * g2 / (4.0 * cos_i * cos_o);
}

// Directional albedo of the white metal at wo = (sin theta_o, 0, cos theta_o): the integral of
// f cos_i over wi, done over half vectors (d wi = 4 (wo.h) d h) with tan theta_h = alpha tan psi and
// psi, phi on an n x 2n midpoint grid: smooth in psi for every alpha.
double textbook_albedo(double roughness, double theta_o, int n) {
  const double alpha = std::max(double(roughness) * roughness, double(BP_GGX_MIN_ALPHA));
  const double wo[3] = {std::sin(theta_o), 0.0, std::cos(theta_o)};
  double sum = 0.0;
  const double dpsi = 0.5 * M_PI / n, dphi = M_PI / n;
  for (int i = 0; i < n; ++i) {
    const double psi = (i + 0.5) * dpsi, t = std::tan(psi);
    const double theta_h = std::atan(alpha * t);
    const double dtheta_dpsi = alpha / (std::cos(psi) * std::cos(psi) * (1.0 + alpha * alpha * t * t));
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = (j + 0.5) * dphi;
      const double h[3] = {std::sin(theta_h) * std::cos(phi), std::sin(theta_h) * std::sin(phi), std::cos(theta_h)};
      const double wo_h = wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2];
      if (wo_h <= 0.0) continue;
      const double cos_i = 2.0 * wo_h * h[2] - wo[2];  // wi = 2 (wo.h) h - wo
      if (cos_i <= 0.0) continue;
      const double f = textbook_specular(roughness, cos_i, wo[2], h[2]);
      sum += f * cos_i * 4.0 * wo_h * std::sin(theta_h) * dtheta_dpsi * dpsi * dphi;
    }
  }
  return sum;
}

// ---------------------------------------------------------------- the shared code against it

TEST(Ggx, SpecularBrdfIsTheTextbookHeightCorrelatedGgx) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (float roughness : {0.1f, 0.2f, 0.5f, 0.8f, 1.0f}) {
    const Material m = make_material(white_metal(roughness));
    const Bsdf b = bsdf_from_material(&m);
    for (int k = 0; k < 2000; ++k) {
      const float3 wi = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
      const float3 wo = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
      const double hx = double(wi.x) + wo.x, hy = double(wi.y) + wo.y, hz = double(wi.z) + wo.z;
      const double cos_h = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
      // F0 = 1: conductor_fresnel is 1, f = specular_brdf
      const double expected = textbook_specular(roughness, wi.z, wo.z, cos_h);
      const float f = bsdf_eval(&b, kNormal, wi, wo).x;
      // float's half vector is off by ~1e-7 rad, which moves D by up to ~4e-7 / alpha^2 of itself
      const double alpha = double(roughness) * roughness, relative = 2e-4 + 4e-7 / (alpha * alpha);
      ASSERT_NEAR(f, expected, relative * std::max(1.0, expected)) << "roughness " << roughness;
    }
  }
}

TEST(Ggx, ProjectedMicrofacetAreaIsOne) {
  // The integral of D(h) cos theta_h over the hemisphere is 1 (Walter et al. 2007, eq. 4).
  for (float alpha : {0.01f, 0.05f, 0.2f, 0.6f, 1.0f}) {
    const int n = 4000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {  // theta_h = atan(alpha tan psi): resolves the peak for every alpha
      const double psi = (i + 0.5) * 0.5 * M_PI / n, t = std::tan(psi), theta = std::atan(alpha * t);
      const double jac = alpha / (std::cos(psi) * std::cos(psi) * (1.0 + double(alpha) * alpha * t * t));
      const float c = float(std::cos(theta)), s = float(std::sin(theta));
      sum += ggx_d(alpha, c, s * s) * c * std::sin(theta) * jac * (0.5 * M_PI / n) * 2 * M_PI;
    }
    EXPECT_NEAR(sum, 1.0, 1e-4) << "alpha " << alpha;
  }
}

TEST(Ggx, VisibleNormalReflectionDensityIntegratesToOneOverTheSphere) {
  // wi = reflect(wo, h) with h from the visible normals covers the sphere once: its density (also
  // where wi falls below the surface) integrates to 1. Midpoint rule around the mirror direction,
  // theta = pi t^3 so sharp lobes are resolved.
  for (float alpha : {0.04f, 0.2f, 0.5f, 1.0f})
    for (double theta_o : {0.0, 0.7, 1.3, 1.52}) {
      const float3 wo = dir_from_angles(theta_o, 0.3);
      const Frame around = frame_from_normal(reflect_about(wo, kNormal));
      const int nt = 3000, np = 600;
      double sum = 0.0;
      for (int i = 0; i < nt; ++i) {
        const double t0 = double(i) / nt, t1 = double(i + 1) / nt, tm = 0.5 * (t0 + t1);
        const double theta = M_PI * tm * tm * tm, dtheta = M_PI * (t1 * t1 * t1 - t0 * t0 * t0);
        for (int j = 0; j < np; ++j) {
          const float3 wi = frame_to_world(&around, dir_from_angles(theta, 2 * M_PI * (j + 0.5) / np));
          const float3 h = normalize(wi + wo);
          const float3 nxh = cross(kNormal, h);
          const double p_uv = ggx_vndf_reflection_pdf_uv(alpha, wo.z, h.z, dot(nxh, nxh));
          sum += p_uv / (2 * M_PI) * std::sin(theta) * dtheta * (2 * M_PI / np);
        }
      }
      EXPECT_NEAR(sum, 1.0, 2e-3) << "alpha " << alpha << ", theta_o " << theta_o;
    }
}

TEST(Ggx, ReciprocalAndNonNegative) {
  const GgxMaterial cases[] = {
      white_metal(0.3f),
      {{0.9f, 0.6f, 0.2f}, 1.0f, 0.2f, 1.0f, {0.04f, 0.04f, 0.04f}},    // gold-ish conductor
      {{0.8f, 0.1f, 0.1f}, 0.0f, 0.4f, 1.0f, {0.04f, 0.04f, 0.04f}},    // red plastic
      {{0.5f, 0.5f, 0.5f}, 0.3f, 0.7f, 0.5f, {0.2f, 0.1f, 0.0f}},       // a mix, coloured specular
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (const GgxMaterial& g : cases) {
    const Material m = make_material(g);
    const Bsdf b = bsdf_from_material(&m);
    for (int i = 0; i < 2000; ++i) {
      const float3 wi = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
      const float3 wo = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
      const float3 a = bsdf_eval(&b, kNormal, wi, wo), c = bsdf_eval(&b, kNormal, wo, wi);
      for (float x : {a.x, a.y, a.z}) ASSERT_GE(x, 0.0f);
      ASSERT_NEAR(a.x, c.x, 1e-4f * std::max(1.0f, a.x));
      ASSERT_NEAR(a.z, c.z, 1e-4f * std::max(1.0f, a.z));
    }
  }
}

// ---------------------------------------------------------------- sampling

// Monte Carlo estimate of the directional albedo at wo with the PT's own sampler (mean of
// f cos / pdf_solid, lost samples counting 0), and its standard error.
struct Estimate {
  double mean = 0.0, std_error = 0.0;
};

Estimate sampled_albedo(const Bsdf& b, float3 wo, int channel, std::uint32_t samples, std::uint32_t seed) {
  double sum = 0.0, sum2 = 0.0;
  for (std::uint32_t i = 0; i < samples; ++i) {
    Rng rng = rng_init(seed, i, 0u);
    const float u_lobe = rng_uniform(&rng), u1 = rng_uniform(&rng), u2 = rng_uniform(&rng);
    const BsdfSample s = bsdf_sample(&b, kNormal, wo, u_lobe, u1, u2);
    double x = 0.0;
    if (s.pdf_uv > 0.0f && s.wi.z > 0.0f) {
      const float f[3] = {s.f.x, s.f.y, s.f.z};
      x = f[channel] * s.wi.z * 2 * M_PI / s.pdf_uv;  // f cos / (pdf_uv / 2 pi)   (7)
    }
    sum += x;
    sum2 += x * x;
  }
  Estimate e;
  e.mean = sum / samples;
  e.std_error = std::sqrt(std::max(0.0, sum2 / samples - e.mean * e.mean) / samples);
  return e;
}

TEST(GgxFurnace, WhiteMetalReflectsGgxSingleScatteringAlbedo) {
  // F0 = 1: every reflection keeps its energy, so what is lost is GGX's single-scattering loss (the
  // light masked and shadowed by microfacets). Reference: quadrature of the textbook f cos above,
  // which shares nothing with the sampler; its own error is bounded by halving the grid.
  const double z = z_for_two_sided(sidak_alpha(1e-3, 4 * 4));
  for (float roughness : {0.2f, 0.5f, 0.8f, 1.0f})
    for (double theta_o : {0.0, 0.6, 1.1, 1.45}) {
      const double reference = textbook_albedo(roughness, theta_o, 1600);
      const double quadrature_error = std::fabs(reference - textbook_albedo(roughness, theta_o, 800));
      const Material m = make_material(white_metal(roughness));
      const Bsdf b = bsdf_from_material(&m);
      const Estimate e = sampled_albedo(b, dir_from_angles(theta_o, 0.0), 0, 1u << 19, 17u);
      EXPECT_NEAR(e.mean, reference, z * e.std_error + quadrature_error)
          << "roughness " << roughness << ", theta_o " << theta_o << " (std error " << e.std_error << ")";
      EXPECT_LE(reference, 1.0 + quadrature_error);  // single scattering never gains energy
      if (roughness == 0.2f && theta_o < 1.0) {
        EXPECT_GT(reference, 0.97);  // a smooth mirror loses little
      }
    }
}

TEST(GgxFurnace, WhiteLambertReflectsEverything) {
  // metallic 0, specular 0: glTF's dielectric_brdf is diffuse_brdf alone, and a white one reflects 1.
  const Material m = make_material({{1, 1, 1}, 0.0f, 0.5f, 0.0f, {0.04f, 0.04f, 0.04f}});
  const Bsdf b = bsdf_from_material(&m);
  for (double theta_o : {0.0, 0.8, 1.4}) {
    const Estimate e = sampled_albedo(b, dir_from_angles(theta_o, 0.0), 1, 1u << 16, 23u);
    EXPECT_NEAR(e.mean, 1.0, 1e-5);  // every sample is f cos / pdf = 1 exactly
  }
  EXPECT_FLOAT_EQ(b.continuation, 1.0f);
}

struct ChiSquareCase {
  const char* name;
  GgxMaterial material;
  double wo_theta;
};

const ChiSquareCase kChiSquareCases[] = {
    {"white_metal_r0.2_normal", white_metal(0.2f), 0.0},
    {"white_metal_r0.2_grazing", white_metal(0.2f), 1.4},
    {"white_metal_r0.5_oblique", white_metal(0.5f), 0.9},
    {"white_metal_r1_oblique", white_metal(1.0f), 0.7},
    {"gold_r0.1", {{0.95f, 0.65f, 0.25f}, 1.0f, 0.1f, 1.0f, {0.04f, 0.04f, 0.04f}}, 0.5},
    {"plastic_r0.4", {{0.7f, 0.1f, 0.1f}, 0.0f, 0.4f, 1.0f, {0.04f, 0.04f, 0.04f}}, 1.2},
    {"dark_plastic_r0.2", {{0.05f, 0.05f, 0.05f}, 0.0f, 0.2f, 1.0f, {0.04f, 0.04f, 0.04f}}, 0.8},
    {"half_metal_r0.6", {{0.5f, 0.5f, 0.5f}, 0.5f, 0.6f, 0.5f, {0.3f, 0.2f, 0.1f}}, 0.3},
};
constexpr int kChiSquareFamily = sizeof(kChiSquareCases) / sizeof(kChiSquareCases[0]);

class GgxChiSquare : public ::testing::TestWithParam<ChiSquareCase> {};

TEST_P(GgxChiSquare, SamplerFollowsTheMixturePdf) {
  const ChiSquareCase& c = GetParam();
  const Material m = make_material(c.material);
  const Bsdf b = bsdf_from_material(&m);
  const float3 wo = dir_from_angles(c.wo_theta, 0.0);
  // Cells in a frame around the mirror direction over a range that grows with the lobe, where a lone
  // specular lobe lies above the horizon (a sharp lobe is resolved, the rest of the sphere is one cell
  // whose expectation is what remains); else the hemisphere about the normal, so that no cell
  // straddles the horizon (where the cells' quadrature would miss the density's edge).
  const double alpha = ggx_alpha_from_roughness(c.material.roughness);
  const double lobe_width = 12.0 * alpha + 0.1;
  const bool around_mirror = c.material.metallic == 1.0f && c.wo_theta + lobe_width < 0.5 * M_PI;
  const Frame frame = frame_from_normal(around_mirror ? reflect_about(wo, kNormal) : kNormal);
  const double theta_max = around_mirror ? lobe_width : 0.5 * M_PI;
  const int n_theta = 24, n_phi = 32;
  std::vector<double> observed(n_theta * n_phi + 1, 0.0), expected(n_theta * n_phi + 1, 0.0);
  const std::size_t rest = observed.size() - 1;
  const std::uint32_t samples = 1u << 20;
  for (std::uint32_t i = 0; i < samples; ++i) {
    Rng rng = rng_init(29u, i, 0u);
    const float u_lobe = rng_uniform(&rng), u1 = rng_uniform(&rng), u2 = rng_uniform(&rng);
    const BsdfSample s = bsdf_sample(&b, kNormal, wo, u_lobe, u1, u2);
    if (!(s.pdf_uv > 0.0f)) { observed[rest] += 1; continue; }  // fell below the surface
    const double theta = std::acos(std::clamp<double>(dot(s.wi, frame.n), -1.0, 1.0));
    double phi = std::atan2(double(dot(s.wi, frame.b)), double(dot(s.wi, frame.t)));
    if (phi < 0) phi += 2 * M_PI;
    if (theta >= theta_max) { observed[rest] += 1; continue; }
    const int it = std::min(n_theta - 1, int(theta / theta_max * n_theta));
    const int ip = std::min(n_phi - 1, int(phi / (2 * M_PI) * n_phi));
    observed[std::size_t(it) * n_phi + ip] += 1;
  }
  double inside = 0.0;
  for (int it = 0; it < n_theta; ++it)
    for (int ip = 0; ip < n_phi; ++ip) {
      double sum = 0.0;
      const int sub = around_mirror || alpha > 0.1 ? 12 : 48;  // a sharp lobe in wide cells: finer quadrature
      const double dt = theta_max / n_theta / sub, dp = 2 * M_PI / n_phi / sub;
      for (int a = 0; a < sub; ++a)
        for (int q = 0; q < sub; ++q) {
          const double theta = (it * sub + a + 0.5) * dt, phi = (ip * sub + q + 0.5) * dp;
          const float3 w = frame_to_world(&frame, dir_from_angles(theta, phi));
          sum += bsdf_pdf_uv(&b, kNormal, w, wo) / (2 * M_PI) * std::sin(theta) * dt * dp;
        }
      expected[std::size_t(it) * n_phi + ip] = sum * samples;
      inside += sum;
    }
  expected[rest] = std::max(0.0, 1.0 - inside) * samples;
  const ChiSquareResult r = chi_square_test(observed, expected);
  EXPECT_GT(r.p_value, sidak_alpha(0.01, kChiSquareFamily))
      << c.name << ": chi2 = " << r.statistic << " with " << r.dof << " dof, p = " << r.p_value;
}

INSTANTIATE_TEST_SUITE_P(Host, GgxChiSquare, ::testing::ValuesIn(kChiSquareCases),
                         [](const auto& info) {
                           std::string s = info.param.name;
                           for (char& ch : s) if (ch == '.') ch = '_';
                           return s;
                         });

// ---------------------------------------------------------------- weight inputs

TEST(GgxWeights, ContinuationAndLobeChoiceDependOnTheMaterialNormalAndWoAlone) {
  // s is a function of the material (docs/design.md §3, condition 1) and the lobe choice of (material,
  // n, wo); a texel's f must not change them (textured.h keeps the patch's density inputs).
  const Material m = make_material({{0.6f, 0.5f, 0.4f}, 0.3f, 0.5f, 1.0f, {0.04f, 0.04f, 0.04f}});
  Bsdf b = bsdf_from_material(&m);
  const float s = b.continuation;
  const float3 wo = dir_from_angles(0.9, 0.2), wi = dir_from_angles(0.4, 2.0);
  const float pdf = bsdf_pdf_uv(&b, kNormal, wi, wo);
  const float p_specular = metallic_roughness_specular_probability(&b.metallic_roughness, wo.z);
  const float3 f_before = bsdf_eval(&b, kNormal, wi, wo);
  TexelMaterial t{};  // a texel's f, its specular textured too (KHR_materials_specular)
  t.base_color = make_float3(0.1f, 0.9f, 0.3f);
  t.metallic = 0.2f;
  t.roughness = 0.1f;
  t.specular_textured = 1;
  t.dielectric_f0 = make_float3(0.5f, 0.2f, 0.9f);
  t.specular_weight = 0.3f;
  bsdf_take_texel(&b, &t);
  EXPECT_NE(bsdf_eval(&b, kNormal, wi, wo).x, f_before.x);
  EXPECT_EQ(b.metallic_roughness.specular_weight, 0.3f);  // f takes the texel's Fresnel
  EXPECT_NE(bsdf_eval(&b, kNormal, wi, wo).x, 0.0f);
  EXPECT_EQ(bsdf_pdf_uv(&b, kNormal, wi, wo), pdf);
  EXPECT_EQ(metallic_roughness_continuation(&b.metallic_roughness), s);
  EXPECT_EQ(metallic_roughness_specular_probability(&b.metallic_roughness, wo.z), p_specular);
  EXPECT_GT(s, 0.0f);
  EXPECT_LE(s, 1.0f);
}

TEST(GgxWeights, EyeProxyBoundsTheDensityOverEveryView) {
  // eye_direct_proxy_pdf_uv must not depend on the view; for GGX it is an upper bound of s p_uv(wi | wo).
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(0, 1);
  for (const GgxMaterial& g : {white_metal(0.2f), GgxMaterial{{0.8f, 0.8f, 0.8f}, 0.0f, 0.5f, 1.0f, {0.04f, 0.04f, 0.04f}},
                               GgxMaterial{{0.3f, 0.3f, 0.3f}, 0.5f, 0.1f, 0.5f, {0.1f, 0.1f, 0.1f}}}) {
    const Material m = make_material(g);
    const Bsdf b = bsdf_from_material(&m);
    for (int i = 0; i < 20000; ++i) {
      const float3 wi = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
      const float3 wo = dir_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng));
      ASSERT_LE(b.continuation * bsdf_pdf_uv(&b, kNormal, wi, wo), eye_direct_proxy_pdf_uv(&b, wi.z) * (1.0f + 1e-5f));
    }
  }
}

}  // namespace
}  // namespace bp::test

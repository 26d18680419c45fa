// The transillumination buffer's rasterizer (kernels/shared/bundle_raster.h) compiled as C++.
#include "kernels/shared/bundle_raster.h"
#include "kernels/shared/frame.h"

#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace bp {
namespace {

BundleIteration grid(float3 omega, float rotation, float ou, float ov, std::uint32_t bins, float radius) {
  BundleIteration it{};
  Frame f = frame_from_normal(omega);
  float3 u = f.t * std::cos(rotation) + f.b * std::sin(rotation), v = cross(omega, u);
  it.omega[0] = omega.x; it.omega[1] = omega.y; it.omega[2] = omega.z;
  it.axis_u[0] = u.x; it.axis_u[1] = u.y; it.axis_u[2] = u.z;
  it.axis_v[0] = v.x; it.axis_v[1] = v.y; it.axis_v[2] = v.z;
  it.bin_size = 2.0f * radius / float(bins);
  it.offset_u = ou;
  it.offset_v = ov;
  it.bins_per_side = bins + 1;
  return it;
}

float3 random_unit(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0, 1);
  float z = 1 - 2 * u(rng), s = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 6.2831853f * u(rng);
  return make_float3(s * std::cos(phi), s * std::sin(phi), z);
}

BundleElement random_element(std::mt19937& rng, float size) {
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  BundleElement e{};
  float3 p = make_float3(u(rng), u(rng), u(rng));
  float3 a = random_unit(rng) * size, b = random_unit(rng) * size;
  e.v0[0] = p.x; e.v0[1] = p.y; e.v0[2] = p.z;
  e.e1[0] = a.x; e.e1[1] = a.y; e.e1[2] = a.z;
  e.e2[0] = b.x; e.e2[1] = b.y; e.e2[2] = b.z;
  e.area = 0.5f * length(cross(a, b));
  float3 n = normalize(cross(a, b));
  e.normal[0] = n.x; e.normal[1] = n.y; e.normal[2] = n.z;
  return e;
}

TEST(BundleRaster, SpansCoverExactlyTheBinCentresInside) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 1);
  for (int trial = 0; trial < 300; ++trial) {
    BundleElement e = random_element(rng, 0.05f + 0.3f * u(rng));
    BundleIteration it = grid(random_unit(rng), 6.28f * u(rng), u(rng), u(rng), 40, 1.0f);
    RasterElement r = raster_setup(&e, &it);
    std::uint32_t brute = 0;
    for (int j = 0; j <= 40; ++j)
      for (int i = 0; i <= 40; ++i) {
        float px = i + 0.5f, py = j + 0.5f;
        float w0 = raster_edge(r.x[1], r.y[1], r.x[2], r.y[2], px, py) * r.orientation;
        float w1 = raster_edge(r.x[2], r.y[2], r.x[0], r.y[0], px, py) * r.orientation;
        float w2 = raster_edge(r.x[0], r.y[0], r.x[1], r.y[1], px, py) * r.orientation;
        brute += (w0 >= 0 && w1 >= 0 && w2 >= 0 && r.inv_double_area != 0.0f) ? 1u : 0u;
      }
    EXPECT_EQ(raster_count(&r), brute) << "trial " << trial;
  }
}

TEST(BundleRaster, DepthIsThePlaneDepthAtTheBinCentre) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0, 1);
  BundleElement e = random_element(rng, 0.4f);
  float3 omega = random_unit(rng);
  BundleIteration it = grid(omega, 1.0f, 0.3f, 0.7f, 64, 1.0f);
  RasterElement r = raster_setup(&e, &it);
  float3 v0 = bp_load3(e.v0), n = bp_load3(e.normal), uax = bp_private3(it.axis_u), vax = bp_private3(it.axis_v);
  for (bp_i32 j = r.j0; j <= r.j1; ++j) {
    bp_i32 first, last;
    raster_row_span(&r, j, &first, &last);
    for (bp_i32 i = first; i <= last; ++i) {
      // The bin centre as a point on the bin plane through the origin, then along omega to the element.
      float x = (i + 0.5f - 32.0f - it.offset_u) * it.bin_size, y = (j + 0.5f - 32.0f - it.offset_v) * it.bin_size;
      float3 q = uax * x + vax * y;
      float t = dot(n, v0 - q) / dot(n, omega);
      EXPECT_NEAR(raster_depth(&r, i, j), dot(q + omega * t, omega), 1e-4f);
    }
  }
}

TEST(BundleRaster, ExpectedCoverageIsProjectedAreaOverBinArea) {
  // Over the random offset, E[bins covered] = A |cos theta| / A_bin exactly: also for an element much
  // smaller than a bin, which covers one bin or none.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  for (float size : {0.02f, 0.3f}) {
    BundleElement e = random_element(rng, size);
    float3 omega = random_unit(rng);
    const double projected = e.area * std::fabs(dot(bp_load3(e.normal), omega));
    const int n = 40000;
    double sum = 0.0, sum2 = 0.0;
    for (int k = 0; k < n; ++k) {
      BundleIteration it = grid(omega, 6.28f * u(rng), u(rng), u(rng), 20, 1.0f);
      RasterElement r = raster_setup(&e, &it);
      double c = raster_count(&r);
      sum += c;
      sum2 += c * c;
    }
    const double bin_area = 0.1 * 0.1, mean = sum / n, var = sum2 / n - mean * mean;
    EXPECT_NEAR(mean, projected / bin_area, 4.5 * std::sqrt(var / n) + 1e-9) << "element size " << size;
  }
}

// Elements rasterize into raster_fragment_bound slots of their own: no direction or grid offset may
// give more. Shapes from round to slivers (the perimeter term matters), sizes from a hundredth of a
// bin to thousands of bins, grids up to 4096 bins (float rounding at the edges).
TEST(BundleRaster, NoElementCoversMoreBinsThanItsBound) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0, 1);
  for (int trial = 0; trial < 20000; ++trial) {
    const std::uint32_t bins = trial % 4 == 0 ? 4096u : 8u + std::uint32_t(200 * u(rng));
    const float bin_size = 2.0f / float(bins), size = bin_size * std::exp(std::log(0.01f) + u(rng) * std::log(3e5f));
    BundleElement e = random_element(rng, std::min(size, 1.0f));
    if (trial % 3 == 0) {  // a sliver: e2 nearly along e1
      float3 a = bp_load3(e.e1), b = a * (0.2f + 0.8f * u(rng)) + random_unit(rng) * (length(a) * 1e-3f * u(rng));
      e.e2[0] = b.x; e.e2[1] = b.y; e.e2[2] = b.z;
      e.area = 0.5f * length(cross(a, b));
    }
    const float3 e1 = bp_load3(e.e1), e2 = bp_load3(e.e2);
    const float perimeter = length(e1) + length(e2) + length(e2 - e1);
    const std::uint32_t bound = raster_fragment_bound(e.area, perimeter, bin_size);
    for (int k = 0; k < 4; ++k) {
      BundleIteration it = grid(random_unit(rng), 6.28f * u(rng), u(rng), u(rng), bins, 1.0f);
      RasterElement r = raster_setup(&e, &it);
      const std::uint32_t covered = raster_count(&r);
      ASSERT_LE(covered, bound) << "trial " << trial << ": area " << e.area / (bin_size * bin_size)
                                << " bins, perimeter " << perimeter / bin_size << " bins";
    }
  }
}

// The cases that come closest to the bound: the element faces omega and its corners sit on bin
// centres (a hair outside them, so that every centre on an edge counts), legs along the grid axes
// or not. Pick's theorem then gives A + B/2 + 1 covered bins, B the centres on the boundary.
TEST(BundleRaster, LatticeTrianglesFacingTheGridStayWithinTheBound) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  const std::uint32_t bins = 256;
  std::uint32_t worst_slack = ~0u;
  for (int trial = 0; trial < 3000; ++trial) {
    float3 omega = random_unit(rng);
    BundleIteration it = grid(omega, 6.28f * u(rng), u(rng), u(rng), bins, 1.0f);
    const float h = it.bin_size, half = 0.5f * float(bins);
    const float3 ax = bp_private3(it.axis_u), ay = bp_private3(it.axis_v);
    auto point = [&](float x, float y) {  // the point whose projection is (x, y) in bin units
      return ax * ((x - half - it.offset_u) * h) + ay * ((y - half - it.offset_v) * h);
    };
    const int i0 = 20 + int(100 * u(rng)), j0 = 20 + int(100 * u(rng));
    const int a = 1 + int(60 * u(rng)), b = trial % 2 ? 1 + int(60 * u(rng)) : 0, c = 1 + int(60 * u(rng));
    // corners (i0, j0), (i0 + a, j0 + b), (i0, j0 + c) at bin centres, pushed 1e-3 bins away from the centroid
    float px[3] = {float(i0), float(i0 + a), float(i0)}, py[3] = {float(j0), float(j0 + b), float(j0 + c)};
    const float cx = (px[0] + px[1] + px[2]) / 3.0f, cy = (py[0] + py[1] + py[2]) / 3.0f;
    float3 corner[3];
    for (int k = 0; k < 3; ++k) {
      const float dx = px[k] - cx, dy = py[k] - cy, d = std::sqrt(dx * dx + dy * dy);
      corner[k] = point(px[k] + 0.5f + 1e-3f * dx / d, py[k] + 0.5f + 1e-3f * dy / d);
    }
    BundleElement e{};
    const float3 e1 = corner[1] - corner[0], e2 = corner[2] - corner[0];
    for (int k = 0; k < 3; ++k) {
      e.v0[k] = (&corner[0].x)[k];
      e.e1[k] = (&e1.x)[k];
      e.e2[k] = (&e2.x)[k];
    }
    e.area = 0.5f * length(cross(e1, e2));
    const float perimeter = length(e1) + length(e2) + length(e2 - e1);
    const std::uint32_t bound = raster_fragment_bound(e.area, perimeter, h);
    RasterElement r = raster_setup(&e, &it);
    const std::uint32_t covered = raster_count(&r);
    ASSERT_LE(covered, bound) << "trial " << trial << ": legs " << a << ", " << b << ", " << c;
    worst_slack = std::min(worst_slack, bound - covered);
  }
  EXPECT_LE(worst_slack, 4u);  // the bound is as tight as its margin: a bound 1 bin lower would fail
}

}  // namespace
}  // namespace bp

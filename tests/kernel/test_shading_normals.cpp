// Shading normals (docs/design.md §6): a coarse UV sphere whose NORMAL corners are the sphere's radial
// directions, lit by a far point light. On a triangle with corners on a sphere the interpolated,
// normalised corner normal at a point p is exactly normalize(p - centre), so the image has a closed
// form on the mesh itself: kd/pi I cos(theta_shading)/d^2 where the flat normal faces the light, 0
// elsewhere (the sphere is convex and alone: no shadow, no indirect light). Facets are several pixels
// wide, so flat shading is visibly different from it, and the test shows it is.
#include "kernel/device_fixture.h"
#include "device/device_scene.h"
#include "kernels/shared/bvh.h"
#include "kernels/shared/camera.h"

#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>

namespace bp::test {
namespace {

constexpr float kRadius = 0.5f;
constexpr double kAlbedo = 0.6;
const glm::dvec3 kLight(40.0, 30.0, 80.0);  // far: RB's patch-level light samples see it from one direction
const double kIntensity = glm::dot(kLight, kLight);  // W/sr: about 1 W/m^2 at the sphere

// A UV sphere of 12 rings and 24 segments (15 degree facets) about the origin, seen from +z.
Scene uv_sphere(bool with_normals) {
  Scene scene;
  SceneMaterial grey;
  grey.kd = glm::vec3(float(kAlbedo));
  scene.materials = {grey};
  const int rings = 12, segments = 24;
  auto vertex = [&](int i, int j) {
    const double theta = M_PI * i / rings, phi = 2.0 * M_PI * j / segments;
    return glm::vec3(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)), float(std::sin(theta) * std::sin(phi))) *
           kRadius;
  };
  auto add = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    if (glm::length(glm::cross(b - a, c - a)) < 1e-9f) return;  // the poles' collapsed corners
    if (glm::dot(glm::cross(b - a, c - a), a + b + c) < 0.0f) std::swap(b, c);  // front faces out
    SceneTriangle t{{a, b, c}, 0};
    t.has_normals = with_normals;
    for (int k = 0; k < 3; ++k) t.normal[k] = glm::normalize(t.p[k]);
    scene.triangles.push_back(t);
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      add(vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1));
      add(vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1));
    }
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  ScenePunctualLight light;
  light.position = glm::vec3(kLight);
  light.intensity = glm::vec3(float(kIntensity));
  scene.lights = {light};
  scene.camera.position = glm::vec3(0.0f, 0.0f, 2.5f);
  scene.camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.yfov = 0.45f;
  return scene;
}

// The closed form of every pixel (mean and standard deviation over a 12x12 sub-pixel grid), from
// the host's own ray casts against the mesh. Pixels near a discontinuity (the silhouette, and the
// facet-wise cut where the flat normal turns from the light) are left out: a sliver of it between
// the grid's points would escape the reference's deviation.
struct PixelReference {
  std::vector<double> mean, sd;
  std::vector<bool> near_edge;
};
PixelReference sphere_reference(const Scene& scene, int size) {
  const FlatBvh bvh = build_bvh(scene.triangles);
  const CameraParams camera = pack_camera(scene.camera, size, size);
  const float3 o = make_float3(camera.position[0], camera.position[1], camera.position[2]);
  const int grid = 12;
  PixelReference ref;
  std::vector<unsigned> kinds_of;  // per pixel
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      double sum = 0.0, sum2 = 0.0;
      unsigned kinds = 0;  // bits: 1 missed, 2 lit, 4 in the shade
      for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
          const float3 d = camera_ray_direction(&camera, std::uint32_t(px), std::uint32_t(py), (i + 0.5f) / grid,
                                                (j + 0.5f) / grid);
          Hit hit;
          double l = 0.0;
          unsigned kind = 1;
          if (bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), o, d, BP_FLOAT_MAX, &hit)) {
            const SceneTriangle& t = scene.triangles[hit.triangle];
            const glm::dvec3 p = glm::dvec3(o.x, o.y, o.z) + glm::dvec3(d.x, d.y, d.z) * double(hit.t);
            const glm::dvec3 flat = glm::normalize(glm::dvec3(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0])));
            const glm::dvec3 to_light = kLight - p, wi = glm::normalize(to_light);
            const double cos_shading = glm::dot(glm::normalize(p), wi);
            kind = 4;
            if (glm::dot(flat, wi) > 0.0 && cos_shading > 0.0) {
              l = kAlbedo / M_PI * kIntensity * cos_shading / glm::dot(to_light, to_light);
              kind = 2;
            }
          }
          kinds |= kind;
          sum += l;
          sum2 += l * l;
        }
      const double mean = sum / (grid * grid);
      ref.mean.push_back(mean);
      ref.sd.push_back(std::sqrt(std::max(0.0, sum2 / (grid * grid) - mean * mean)));
      kinds_of.push_back(kinds);
    }
  ref.near_edge.assign(kinds_of.size(), false);
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      unsigned around = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = std::clamp(px + dx, 0, size - 1), y = std::clamp(py + dy, 0, size - 1);
          around |= kinds_of[std::size_t(y) * size + x];
        }
      ref.near_edge[std::size_t(py) * size + px] = (around & (around - 1)) != 0;  // more than one kind
    }
  return ref;
}

// Pixels of `image` (scaled by `share`) further from the reference than 5 standard errors of
// `jitters` jittered samples (plus float rounding); and how many pixels the sphere covers.
struct Mismatch {
  int bad = 0, lit = 0;
  std::string first;
};
Mismatch compare(const ImageRGB& image, const PixelReference& ref, int size, double share, double jitters) {
  Mismatch m;
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      const std::size_t i = std::size_t(py) * size + px;
      if (ref.near_edge[i]) continue;
      const double mean = share * ref.mean[i], bound = 5.0 * share * ref.sd[i] / std::sqrt(jitters) + 2e-3 * mean + 1e-6;
      if (mean > 0.01) ++m.lit;
      for (int c = 0; c < 3; ++c)
        if (std::fabs(image.pixel(px, py)[c] - mean) > bound) {
          if (m.bad++ == 0)
            m.first = "pixel " + std::to_string(px) + "," + std::to_string(py) + ": " +
                      std::to_string(image.pixel(px, py)[c]) + " vs " + std::to_string(mean) + " +- " +
                      std::to_string(bound);
          break;
        }
    }
  return m;
}

constexpr int kSize = 40;

TEST(ShadingNormals, PathTracedSmoothSphereMatchesTheClosedForm) {
  const Scene smooth = uv_sphere(true);
  const PixelReference ref = sphere_reference(smooth, kSize);
  const int spp = 64;
  const Mismatch m = compare(render_pt(smooth, kSize, kSize, spp, 3).image, ref, kSize, 1.0, spp);
  EXPECT_EQ(m.bad, 0) << m.first;
  EXPECT_GT(m.lit, kSize * kSize / 4) << "the light did not reach the sphere: the test would prove nothing";
  // The same mesh without NORMAL is faceted, and the test sees it.
  const Mismatch flat = compare(render_pt(uv_sphere(false), kSize, kSize, spp, 3).image, ref, kSize, 1.0, spp);
  EXPECT_GT(flat.bad, m.lit / 5) << "flat shading passes too: the test cannot tell shading normals apart";
}

// The combination with the eye vertex's direct light shared: a delta light's share is fixed,
// c/(c + 1) to RB's per-patch light samples (c = N2/N1 x rate) and the rest to PT, so each layer
// has its own closed form; RB's eye gather reflects its patches' light with the shading normal.
TEST(ShadingNormals, CombinedSmoothSphereMatchesTheClosedFormInEachLayer) {
  const Scene smooth = uv_sphere(true);
  const PixelReference ref = sphere_reference(smooth, kSize);
  CombinedSettings cs;
  cs.light_sampling = true;
  cs.eye_direct_shared = true;
  cs.pt_samples_per_round = 1;
  cs.rb_iterations_per_round = 4;
  cs.rounds = 64;
  cs.patch_size = 0.05f;
  cs.light_rate = 1.0f;
  const CombinedRun run = render_combined(smooth, kSize, kSize, cs);
  const double c = 4.0 * cs.light_rate, rb_share = c / (c + 1.0);
  const double rb_jitters = double(cs.rounds * cs.rb_iterations_per_round) / 16.0;  // jitter_refresh
  const Mismatch pt = compare(run.pt, ref, kSize, 1.0 - rb_share, double(cs.rounds));
  EXPECT_EQ(pt.bad, 0) << "pt layer: " << pt.first;
  const Mismatch rb = compare(run.rb, ref, kSize, rb_share, rb_jitters);
  EXPECT_EQ(rb.bad, 0) << "rb layer: " << rb.first;
  EXPECT_GT(rb.lit, kSize * kSize / 4);
  // RB's eye gather without NORMAL is faceted, and the test sees it.
  cs.rounds = 16;
  const Mismatch flat = compare(render_combined(uv_sphere(false), kSize, kSize, cs).rb, ref, kSize, rb_share,
                                double(cs.rounds * cs.rb_iterations_per_round) / 16.0);
  EXPECT_GT(flat.bad, rb.lit / 5) << "flat shading passes too: the test cannot tell shading normals apart";
}

// A scene without NORMAL pays nothing for them: no buffer beyond the one dummy entry.
TEST(ShadingNormals, ScenesWithoutNormalsUploadNone) {
  EXPECT_TRUE(pack_shading_normals(uv_sphere(false)).empty());
  EXPECT_EQ(pack_shading_normals(uv_sphere(true)).size(), 9 * uv_sphere(true).triangles.size());
}

}  // namespace
}  // namespace bp::test

#include "ray_set.h"

#include <cmath>
#include <utility>

namespace bp::bench {
namespace {

float3 to_f3(const glm::vec3& v) { return make_float3(v.x, v.y, v.z); }

// Camera rays through a 256 x 192 grid, then from each hit a cosine-distributed bounce leaving
// the side of the surface the camera ray came from.
}  // namespace

RaySet make_rays(const bp::Scene& scene, const bp::FlatBvh& bvh) {
  const int width = 256, height = 192;
  const bp::SceneCamera& cam = scene.camera;
  glm::vec3 right = glm::normalize(glm::cross(cam.forward, cam.up));
  float tan_y = std::tan(0.5f * cam.yfov), tan_x = tan_y * width / height;
  float epsilon = 1e-4f * glm::length(scene.bounds.extent());
  RaySet rays;
  std::uint32_t state = 12345u;
  auto uniform = [&] {  // xorshift32
    state ^= state << 13; state ^= state >> 17; state ^= state << 5;
    return static_cast<float>(state >> 8) * (1.0f / 16777216.0f);
  };
  std::vector<std::pair<glm::vec3, glm::vec3>> bounces;
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px) {
      float sx = (2.0f * (px + uniform()) / width - 1.0f) * tan_x;
      float sy = (1.0f - 2.0f * (py + uniform()) / height) * tan_y;
      glm::vec3 d = glm::normalize(cam.forward + sx * right + sy * cam.up);
      rays.origin.push_back(to_f3(cam.position));
      rays.dir.push_back(to_f3(d));
      Hit hit;
      if (!bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), to_f3(cam.position), to_f3(d),
                           INFINITY, &hit))
        continue;
      const bp::SceneTriangle& tri = scene.triangles[hit.triangle];
      glm::vec3 n = glm::normalize(glm::cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]));
      if (glm::dot(n, d) > 0.0f) n = -n;
      glm::vec3 p = cam.position + hit.t * d + epsilon * n;
      glm::vec3 t = glm::normalize(glm::cross(std::fabs(n.x) > 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0), n));
      glm::vec3 b = glm::cross(n, t);
      float r = std::sqrt(uniform()), phi = 6.2831853f * uniform();
      glm::vec3 bounce = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1 - r * r)) * n;
      bounces.emplace_back(p, glm::normalize(bounce));
    }
  for (const auto& [p, d] : bounces) {
    rays.origin.push_back(to_f3(p));
    rays.dir.push_back(to_f3(d));
  }
  return rays;
}

}  // namespace bp::bench

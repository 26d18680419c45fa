#include "scene/tangents.h"

#include <cmath>

namespace bp {

glm::vec3 any_tangent(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);  // "Building an Orthonormal Basis, Revisited" (Duff et al. 2017)
  const float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
  return glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
}

namespace {

// v normalised; zero where it has no length.
glm::vec3 unit_or_zero(const glm::vec3& v) {
  const float len = glm::length(v);
  return len > 1e-20f && std::isfinite(len) ? v / len : glm::vec3(0.0f);
}

// v without its component along unit n, normalised; zero where nothing is left.
glm::vec3 in_plane(const glm::vec3& v, const glm::vec3& n) { return unit_or_zero(v - n * glm::dot(n, v)); }

float corner_angle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {  // at a
  const float lb = glm::length(b - a), lc = glm::length(c - a);
  if (!(lb > 0.0f && lc > 0.0f)) return 0.0f;
  return std::acos(glm::clamp(glm::dot(b - a, c - a) / (lb * lc), -1.0f, 1.0f));
}

}  // namespace

GeneratedTangents generate_tangents(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& given_normals,
                                    const std::vector<glm::vec2>& uvs,
                                    const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  const std::size_t n = positions.size();
  std::vector<glm::vec3> sum_t(n, glm::vec3(0.0f)), sum_b(n, glm::vec3(0.0f)), normals(n);
  for (std::size_t v = 0; v < n; ++v) normals[v] = unit_or_zero(given_normals[v]);
  for (const auto& tri : triangles) {
    const glm::vec3 e1 = positions[tri[1]] - positions[tri[0]], e2 = positions[tri[2]] - positions[tri[0]];
    const glm::vec2 d1 = uvs[tri[1]] - uvs[tri[0]], d2 = uvs[tri[2]] - uvs[tri[0]];
    const float det = d1.x * d2.y - d2.x * d1.y;  // of the uv map's edges
    if (!(std::fabs(det) > 0.0f)) continue;       // degenerate UVs: no direction from this triangle
    // e = (du) T + (dv) V over both edges solved for T = dp/du and V = dp/dv; B = -V (image up)
    const glm::vec3 t = (e1 * d2.y - e2 * d1.y) / det;
    const glm::vec3 b = -(e2 * d1.x - e1 * d2.x) / det;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = tri[k];
      const float angle = corner_angle(positions[v], positions[tri[(k + 1) % 3]], positions[tri[(k + 2) % 3]]);
      sum_t[v] += in_plane(t, normals[v]) * angle;  // MikkTSpace's weighting: the corner's angle
      sum_b[v] += in_plane(b, normals[v]) * angle;
    }
  }
  GeneratedTangents out;
  out.tangents.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    glm::vec3 t = in_plane(sum_t[v], normals[v]);  // Gram-Schmidt against the vertex normal
    if (t == glm::vec3(0.0f)) {
      out.tangents[v] = glm::vec4(any_tangent(normals[v]), 1.0f);
      ++out.fallbacks;
      continue;
    }
    const float w = glm::dot(glm::cross(normals[v], t), sum_b[v]) < 0.0f ? -1.0f : 1.0f;  // handedness
    out.tangents[v] = glm::vec4(t, w);
  }
  return out;
}

}  // namespace bp

#include "scene/lights.h"

#include <algorithm>
#include <cmath>

namespace bp {
namespace {

float mean(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

void store3(float* out, const glm::vec3& v) {
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}

}  // namespace

double sunlit_area(const Scene& scene, const FlatBvh& bvh, const glm::vec3& axis, int grid) {
  const glm::vec3 dir = glm::normalize(axis);
  const float radius = 0.5f * glm::length(scene.bounds.extent());
  if (!(radius > 0.0f) || scene.triangles.empty() || bvh.nodes.empty() || grid < 1) return 0.0;
  // An orthonormal frame (u, v) of the plane across the light, the disk's centre 2 radii upstream.
  const glm::vec3 helper = std::abs(dir.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::vec3 u = glm::normalize(glm::cross(dir, helper)), v = glm::cross(dir, u);
  const glm::vec3 start = scene.bounds.centre() - 2.0f * radius * dir;
  const double cell = 2.0 * double(radius) / grid;
  std::uint64_t lit = 0;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const float x = float(-radius + (i + 0.5) * cell), y = float(-radius + (j + 0.5) * cell);
      if (x * x + y * y > radius * radius) continue;
      const glm::vec3 o = start + x * u + y * v;
      Hit hit;
      if (!bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), make_float3(o.x, o.y, o.z),
                           make_float3(dir.x, dir.y, dir.z), BP_FLOAT_MAX, &hit))
        continue;
      const SceneTriangle& t = scene.triangles[hit.triangle];
      const glm::vec3 front = glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);  // counter-clockwise = front
      if (glm::dot(front, dir) < 0.0f || scene.materials[t.material].double_sided) ++lit;
    }
  return double(lit) * cell * cell;
}

LightList build_light_list(const Scene& scene, const FlatBvh& bvh) {
  LightList out;
  std::vector<double> power;
  // Emitted power per unit area of each material: pi Le per side.
  std::vector<double> exitance(scene.materials.size(), 0.0);
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    const SceneMaterial& mat = scene.materials[m];
    exitance[m] = M_PI * double(mean(mat.emission)) * (mat.double_sided ? 2.0 : 1.0);
  }
  out.light_of_triangle.assign(scene.triangles.size(), BP_NO_LIGHT);
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const SceneTriangle& t = scene.triangles[i];
    if (!(exitance[t.material] > 0.0)) continue;
    out.light_of_triangle[i] = std::uint32_t(out.lights.size());
    const glm::vec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], c = glm::cross(e1, e2);
    Light l{};
    l.type = BP_LIGHT_TRIANGLE;
    store3(l.position, t.p[0]);
    store3(l.edge1, e1);
    store3(l.edge2, e2);
    store3(l.axis, glm::normalize(c));
    l.area = 0.5f * glm::length(c);
    l.material = t.material;
    l.triangle = std::uint32_t(i);
    out.lights.push_back(l);
    power.push_back(exitance[t.material] * double(l.area));
  }
  const double scene_radius = 0.5 * double(glm::length(scene.bounds.extent()));
  std::vector<const ScenePunctualLight*> punctual;  // point and spot lights, then directional ones (lights.h)
  for (const ScenePunctualLight& p : scene.lights)
    if (p.kind != ScenePunctualLight::Kind::directional) punctual.push_back(&p);
  for (const ScenePunctualLight& p : scene.lights)
    if (p.kind == ScenePunctualLight::Kind::directional) punctual.push_back(&p);
  for (const ScenePunctualLight* light : punctual) {
    const ScenePunctualLight& p = *light;
    Light l{};
    store3(l.position, p.position);
    store3(l.axis, p.direction);
    store3(l.intensity, p.intensity);
    l.cos_inner = std::cos(p.inner_cone);
    l.cos_outer = std::cos(p.outer_cone);
    double solid_angle = 4.0 * M_PI;
    if (p.kind == ScenePunctualLight::Kind::directional) {
      l.type = BP_LIGHT_DIRECTIONAL;
      // Not a solid angle: the area, across the light, of what the sun falls on first (a
      // heuristic: a room lit through a window gets the window's share, not the whole roof's), at
      // least one grid cell's, so a sun that the grid finds nowhere is still chosen now and then.
      const double cell_side = 2.0 * scene_radius / kSunlitGrid;
      solid_angle = std::max(sunlit_area(scene, bvh, p.direction, kSunlitGrid), cell_side * cell_side);
    } else if (p.kind == ScenePunctualLight::Kind::spot) {
      l.type = BP_LIGHT_SPOT;
      // the cone out to the middle of the falloff: a selection heuristic, not part of the estimate
      solid_angle = 2.0 * M_PI * (1.0 - 0.5 * (double(l.cos_inner) + double(l.cos_outer)));
    } else {
      l.type = BP_LIGHT_POINT;
    }
    const double light_power = solid_angle * double(mean(p.intensity));
    if (!(light_power > 0.0)) continue;  // dark: never chosen
    out.lights.push_back(l);
    power.push_back(light_power);
  }
  // The environment, last: the power it sends into the scene's bounding sphere, pi R^2 times its
  // integral over directions (exact for a uniform one: pi L 4 pi R^2).
  const std::shared_ptr<const EnvironmentImage> environment = scene.environment_map();
  const double environment_power =
      environment->empty() ? 0.0 : M_PI * scene_radius * scene_radius * environment_integral(*environment);
  if (environment_power > 0.0) {
    Light l{};
    l.type = BP_LIGHT_ENVIRONMENT;
    out.environment_light = std::uint32_t(out.lights.size());
    out.lights.push_back(l);
    power.push_back(environment_power);
  }
  for (double w : power) out.total_power += w;
  if (!(out.total_power > 0.0) || !std::isfinite(out.total_power)) {
    LightList none;
    none.light_of_triangle.assign(scene.triangles.size(), BP_NO_LIGHT);
    return none;
  }
  double running = 0.0;
  for (std::size_t i = 0; i < out.lights.size(); ++i) {
    out.lights[i].select_probability = float(power[i] / out.total_power);
    running += power[i];
    out.cdf.push_back(i + 1 == out.lights.size() ? 1.0f : float(running / out.total_power));
  }
  // P(select triangle) / area = exitance / total power: the same for every triangle of a material.
  out.material_pdf_area.resize(scene.materials.size());
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    out.material_pdf_area[m] = float(exitance[m] / out.total_power);
  return out;
}

}  // namespace bp

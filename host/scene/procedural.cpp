// Procedural scenes: a splitmix64 stream per scene, so a (size, seed) pair gives the same scene
// with every compiler and standard library.
#include "scene/procedural.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace bp {
namespace {

class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }  // [0,1)
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::uint64_t state_;
};

void finish(Scene& scene) {
  scene.bounds = Bounds{};
  for (const SceneTriangle& tri : scene.triangles)
    for (const glm::vec3& p : tri.p) scene.bounds.grow(p);
}

// A rectangle corner + s u + t v, s, t in [0,1]; its front side faces u x v.
struct Quad {
  glm::vec3 corner, u, v;
  std::uint32_t material;
  bool tessellate;
};

int cells(const glm::vec3& edge, float size) {
  return std::max(1, static_cast<int>(std::ceil(glm::length(edge) / size - 1e-4f)));
}

std::size_t triangle_count(const std::vector<Quad>& quads, float size) {
  std::size_t n = 0;
  for (const Quad& q : quads)
    n += q.tessellate ? 2 * std::size_t(cells(q.u, size)) * std::size_t(cells(q.v, size)) : 2;
  return n;
}

void emit(const Quad& q, float size, std::vector<SceneTriangle>& out) {
  int nu = q.tessellate ? cells(q.u, size) : 1, nv = q.tessellate ? cells(q.v, size) : 1;
  auto at = [&](int i, int j) {
    return q.corner + q.u * (static_cast<float>(i) / nu) + q.v * (static_cast<float>(j) / nv);
  };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      glm::vec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      out.push_back({{a, b, c}, q.material});
      out.push_back({{a, c, d}, q.material});
    }
}

// Wall in the vertical plane through `start` along unit `along`, its front facing along x up
// (or up x along); with a doorway (1 m x 2.1 m) starting `door_at` metres along it when door_at >= 0.
void add_wall(std::vector<Quad>& quads, glm::vec3 start, glm::vec3 along, float length,
              float height, float door_at, bool front_along_x_up, std::uint32_t material) {
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  const float door_width = 1.0f, door_height = 2.1f;
  auto piece = [&](float s0, float s1, float h0, float h1) {
    glm::vec3 corner = start + along * s0 + up * h0;
    glm::vec3 u = along * (s1 - s0), v = up * (h1 - h0);
    if (front_along_x_up) quads.push_back({corner, u, v, material, true});
    else quads.push_back({corner, v, u, material, true});
  };
  if (door_at < 0.0f) {
    piece(0.0f, length, 0.0f, height);
  } else {
    piece(0.0f, door_at, 0.0f, height);
    piece(door_at + door_width, length, 0.0f, height);
    piece(door_at, door_at + door_width, door_height, height);
  }
}

// Closed box standing on the floor, faces outward, no bottom.
void add_box(std::vector<Quad>& quads, glm::vec3 lo, glm::vec3 hi, std::uint32_t material) {
  glm::vec3 e = hi - lo;
  glm::vec3 x(e.x, 0, 0), y(0, e.y, 0), z(0, 0, e.z);
  quads.push_back({glm::vec3(lo.x, hi.y, lo.z), z, x, material, true});  // top, +y
  quads.push_back({lo, z, y, material, true});                            // -x
  quads.push_back({glm::vec3(hi.x, lo.y, lo.z), y, z, material, true});  // +x
  quads.push_back({lo, y, x, material, true});                            // -z
  quads.push_back({glm::vec3(lo.x, lo.y, hi.z), x, y, material, true});  // +z
}

}  // namespace

Scene make_random_triangles_scene(std::size_t n, std::uint32_t seed) {
  Scene scene;
  scene.source = "procedural:random_triangles(" + std::to_string(n) + "," + std::to_string(seed) + ")";
  SceneMaterial diffuse;
  diffuse.name = "diffuse";
  diffuse.kd = glm::vec3(0.7f);
  SceneMaterial light;
  light.name = "light";
  light.kd = glm::vec3(0.0f);
  light.emission = glm::vec3(5.0f);
  light.double_sided = true;
  scene.materials = {diffuse, light};

  Random rng(seed);
  float size = std::min(0.5f, 9.0f / std::sqrt(static_cast<float>(std::max<std::size_t>(n, 1))));
  scene.triangles.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 c(rng.uniform(), rng.uniform(), rng.uniform());
    SceneTriangle tri;
    for (glm::vec3& p : tri.p)
      p = c + size * glm::vec3(rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f));
    tri.material = (rng.next() & 63u) == 0 ? 1u : 0u;
    scene.triangles.push_back(tri);
  }
  scene.camera.position = glm::vec3(0.5f, 0.5f, 2.3f);
  scene.camera.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  scene.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  scene.camera.yfov = 0.75f;
  finish(scene);
  return scene;
}

int rooms_for_triangles(std::size_t target_triangles) {
  return std::max(1, static_cast<int>(std::lround(std::sqrt(target_triangles / 4000.0))));
}

Scene make_rooms_scene(std::size_t target_triangles, std::uint32_t seed, int rooms_per_side) {
  enum : std::uint32_t { kWall, kWallDouble, kFloor, kCeiling, kFurniture, kLight };
  const int grid = rooms_per_side > 0 ? rooms_per_side : rooms_for_triangles(target_triangles);
  // The default grid keeps the old name, so asking for it explicitly writes the same file.
  const std::string rooms_tag = grid == rooms_for_triangles(target_triangles)
                                    ? std::string()
                                    : "," + std::to_string(grid) + "x" + std::to_string(grid) + " rooms";
  Scene scene;
  scene.source =
      "procedural:rooms(" + std::to_string(target_triangles) + "," + std::to_string(seed) + rooms_tag + ")";
  scene.materials.resize(6);
  scene.materials[kWall] = {"wall", glm::vec3(0.75f, 0.75f, 0.72f), glm::vec3(0.0f), 1.0f, glm::vec3(0.0f), false};
  scene.materials[kWallDouble] = {"wall_double", glm::vec3(0.75f, 0.75f, 0.72f), glm::vec3(0.0f), 1.0f,
                                  glm::vec3(0.0f), true};
  scene.materials[kFloor] = {"floor", glm::vec3(0.55f, 0.45f, 0.35f), glm::vec3(0.05f), 20.0f, glm::vec3(0.0f), false};
  scene.materials[kCeiling] = {"ceiling", glm::vec3(0.8f), glm::vec3(0.0f), 1.0f, glm::vec3(0.0f), false};
  scene.materials[kFurniture] = {"furniture", glm::vec3(0.4f, 0.5f, 0.6f), glm::vec3(0.2f), 40.0f,
                                 glm::vec3(0.0f), false};
  scene.materials[kLight] = {"light", glm::vec3(0.0f), glm::vec3(0.0f), 1.0f, glm::vec3(10.0f), false};

  const float width = 5.0f, depth = 4.0f, height = 2.8f;  // room extent along x, z, y
  const glm::vec3 x_axis(1, 0, 0), z_axis(0, 0, 1);
  Random rng(seed);
  std::vector<Quad> quads;
  for (int k = 0; k <= grid; ++k)
    for (int i = 0; i < grid; ++i) {
      bool outer = k == 0 || k == grid;
      // walls along x at z = k depth (front faces +z at k = 0), and along z at x = k width
      add_wall(quads, glm::vec3(i * width, 0, k * depth), x_axis, width, height,
               outer ? -1.0f : rng.uniform(0.5f, width - 1.5f), k != grid, outer ? kWall : kWallDouble);
      add_wall(quads, glm::vec3(k * width, 0, i * depth), z_axis, depth, height,
               outer ? -1.0f : rng.uniform(0.5f, depth - 1.5f), k == grid, outer ? kWall : kWallDouble);
    }
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      glm::vec3 o(i * width, 0, j * depth);
      quads.push_back({o, z_axis * depth, x_axis * width, kFloor, true});
      quads.push_back({o + glm::vec3(0, height, 0), x_axis * width, z_axis * depth, kCeiling, true});
      const float panel = 1.2f;
      glm::vec3 pc = o + glm::vec3(0.5f * (width - panel), height - 0.02f, 0.5f * (depth - panel));
      quads.push_back({pc, x_axis * panel, z_axis * panel, kLight, false});
      int boxes = 2 + static_cast<int>(rng.next() % 3);
      for (int b = 0; b < boxes; ++b) {
        glm::vec3 size(rng.uniform(0.5f, 1.6f), rng.uniform(0.4f, 1.0f), rng.uniform(0.5f, 1.2f));
        glm::vec3 lo = o + glm::vec3(rng.uniform(0.3f, width - 0.3f - size.x), 0.0f,
                                     rng.uniform(0.3f, depth - 0.3f - size.z));
        add_box(quads, lo, lo + size, kFurniture);
      }
    }

  // The largest cell size whose tessellation reaches the target (bisection; the count only
  // grows as cells shrink).
  float coarse = std::max(width, std::max(depth, height)), fine = 1e-3f;
  if (triangle_count(quads, coarse) >= target_triangles) {
    fine = coarse;
  } else {
    for (int it = 0; it < 60; ++it) {
      float mid = std::sqrt(coarse * fine);
      if (triangle_count(quads, mid) >= target_triangles) fine = mid;
      else coarse = mid;
    }
    if (triangle_count(quads, fine) - target_triangles > target_triangles - triangle_count(quads, coarse))
      fine = coarse;
  }
  scene.triangles.reserve(triangle_count(quads, fine));
  for (const Quad& q : quads) emit(q, fine, scene.triangles);

  scene.camera.position = glm::vec3(0.6f, 1.6f, 0.6f);
  scene.camera.forward = glm::normalize(glm::vec3(width - 0.6f, 1.0f - 1.6f, depth - 0.6f));
  glm::vec3 right = glm::normalize(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)));
  scene.camera.up = glm::cross(right, scene.camera.forward);
  scene.camera.yfov = 0.9f;
  finish(scene);
  return scene;
}

}  // namespace bp

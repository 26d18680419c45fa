// Host throughput of the shared BVH traversal (kernels/shared/bvh.h compiled as C++), one thread,
// on a fixed incoherent ray set: camera rays, plus one cosine-distributed bounce from each camera
// hit. Every ray traced is counted, both kinds.
#include "scene/bvh.h"
#include "scene/procedural.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

namespace {

enum SceneKind { kRandom = 0, kRooms = 1 };

struct RaySet {
  std::vector<float3> origin, dir;
};

struct Fixture {
  bp::Scene scene;
  bp::FlatBvh bvh;
  RaySet rays;
};

float3 to_f3(const glm::vec3& v) { return make_float3(v.x, v.y, v.z); }

// Camera rays through a 256 x 192 grid, then from each hit a cosine-distributed bounce leaving
// the side of the surface the camera ray came from.
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

Fixture& fixture(int kind, std::size_t n) {
  static std::map<std::pair<int, std::size_t>, std::unique_ptr<Fixture>> cache;
  auto& slot = cache[{kind, n}];
  if (!slot) {
    slot = std::make_unique<Fixture>();
    slot->scene = kind == kRandom ? bp::make_random_triangles_scene(n, 1) : bp::make_rooms_scene(n, 1);
    slot->bvh = bp::build_bvh(slot->scene.triangles);
    slot->rays = make_rays(slot->scene, slot->bvh);
  }
  return *slot;
}

void set_label(benchmark::State& state, const Fixture& f) {
  state.SetLabel(std::string(state.range(0) == kRandom ? "random" : "rooms") + " " +
                 std::to_string(f.scene.triangles.size()) + " tris");
}

void BM_ClosestHit(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  const BvhNode* nodes = f.bvh.nodes.data();
  const BvhTriangle* tris = f.bvh.triangles.data();
  std::size_t n = f.rays.origin.size();
  for (auto _ : state) {
    std::uint32_t hits = 0;
    for (std::size_t i = 0; i < n; ++i) {
      Hit hit;
      hits += bvh_closest_hit(nodes, tris, f.rays.origin[i], f.rays.dir[i], INFINITY, &hit);
    }
    benchmark::DoNotOptimize(hits);
  }
  state.counters["Mrays"] = benchmark::Counter(n / 1e6, benchmark::Counter::kIsIterationInvariantRate);  // per CPU second
  set_label(state, f);
}

void BM_Occluded(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  const BvhNode* nodes = f.bvh.nodes.data();
  const BvhTriangle* tris = f.bvh.triangles.data();
  std::size_t n = f.rays.origin.size();
  for (auto _ : state) {
    std::uint32_t hits = 0;
    for (std::size_t i = 0; i < n; ++i)
      hits += bvh_occluded(nodes, tris, f.rays.origin[i], f.rays.dir[i], INFINITY);
    benchmark::DoNotOptimize(hits);
  }
  state.counters["Mrays"] = benchmark::Counter(n / 1e6, benchmark::Counter::kIsIterationInvariantRate);  // per CPU second
  set_label(state, f);
}

void BM_Build(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(bp::build_bvh(f.scene.triangles).nodes.data());
  set_label(state, f);
}

void scene_sizes(benchmark::internal::Benchmark* b) {
  for (int kind : {kRooms, kRandom})
    for (long n : {1000L, 100000L, 1000000L}) b->Args({kind, n});
}

}  // namespace

BENCHMARK(BM_ClosestHit)->Apply(scene_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Occluded)->Apply(scene_sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Build)->Apply(scene_sizes)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();

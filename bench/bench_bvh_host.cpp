// Host throughput of the shared BVH traversal (kernels/shared/bvh.h compiled as C++), one thread,
// on a fixed incoherent ray set: camera rays, plus one cosine-distributed bounce from each camera
// hit. Every ray traced is counted, both kinds.
#include "ray_set.h"
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

using bp::bench::RaySet;

struct Fixture {
  bp::Scene scene;
  bp::FlatBvh bvh;
  RaySet rays;
};

Fixture& fixture(int kind, std::size_t n) {
  static std::map<std::pair<int, std::size_t>, std::unique_ptr<Fixture>> cache;
  auto& slot = cache[{kind, n}];
  if (!slot) {
    slot = std::make_unique<Fixture>();
    slot->scene = kind == kRandom ? bp::make_random_triangles_scene(n, 1) : bp::make_rooms_scene(n, 1);
    slot->bvh = bp::build_bvh(slot->scene.triangles);
    slot->rays = bp::bench::make_rays(slot->scene, slot->bvh);
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

// BVH build and traversal (kernels/shared/bvh.h compiled as C++) against brute force over every
// triangle, on random, degenerate and architectural scenes, and the tree's structural invariants.
#include "scene/bvh.h"
#include "scene/procedural.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace bp {
namespace {

float3 f3(const glm::vec3& v) { return make_float3(v.x, v.y, v.z); }

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  float uniform() {  // [0, 1)
    s_ ^= s_ << 13; s_ ^= s_ >> 7; s_ ^= s_ << 17;
    return static_cast<float>(s_ >> 40) * (1.0f / 16777216.0f);
  }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  glm::vec3 direction() {
    float z = uniform(-1.0f, 1.0f), phi = 6.2831853f * uniform(), r = std::sqrt(std::max(0.0f, 1 - z * z));
    return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
  }

 private:
  std::uint64_t s_;
};

struct Ray {
  glm::vec3 origin, dir;
  float t_max;
};

// Every leaf triangle tested in turn: the same arithmetic as the traversal, none of its pruning.
struct BruteForce {
  bool hit = false;
  Hit h{};
  std::uint32_t leaf_index = 0;
};
BruteForce brute_force(const FlatBvh& bvh, const Ray& ray) {
  BruteForce r;
  float t = ray.t_max, b1 = 0, b2 = 0;
  for (std::uint32_t i = 0; i < bvh.triangles.size(); ++i)
    if (bvh_intersect_triangle(&bvh.triangles[i], f3(ray.origin), f3(ray.dir), &t, &b1, &b2)) {
      r.hit = true;
      r.leaf_index = i;
    }
  if (r.hit) r.h = Hit{t, b1, b2, bvh.triangles[r.leaf_index].triangle};
  return r;
}

// Closest hit and occlusion agree with brute force; the barycentrics rebuild the hit point from the
// scene triangle's own vertex order. Returns how many rays hit.
int check_rays(const Scene& scene, const FlatBvh& bvh, const std::vector<Ray>& rays) {
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    SCOPED_TRACE(testing::Message() << "ray " << i << " origin (" << ray.origin.x << ", " << ray.origin.y
                                    << ", " << ray.origin.z << ") dir (" << ray.dir.x << ", " << ray.dir.y
                                    << ", " << ray.dir.z << ") t_max " << ray.t_max);
    BruteForce ref = brute_force(bvh, ray);
    Hit hit{};
    bool found = bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), f3(ray.origin), f3(ray.dir), ray.t_max, &hit);
    bool occluded = bvh_occluded(bvh.nodes.data(), bvh.triangles.data(), f3(ray.origin), f3(ray.dir), ray.t_max);
    EXPECT_EQ(found, ref.hit);
    EXPECT_EQ(occluded, ref.hit);
    if (found != ref.hit) return hits;
    if (!found) continue;
    ++hits;
    EXPECT_GT(hit.t, 0.0f);
    EXPECT_LT(hit.t, ray.t_max);
    EXPECT_NEAR(hit.t, ref.h.t, 1e-5f * ref.h.t);
    if (hit.triangle == ref.h.triangle) {
      EXPECT_NEAR(hit.b1, ref.h.b1, 1e-5f);
      EXPECT_NEAR(hit.b2, ref.h.b2, 1e-5f);
    }
    const SceneTriangle& tri = scene.triangles.at(hit.triangle);
    EXPECT_GE(hit.b1, 0.0f);
    EXPECT_GE(hit.b2, 0.0f);
    EXPECT_LE(hit.b1 + hit.b2, 1.0f + 1e-6f);
    glm::vec3 p = (1 - hit.b1 - hit.b2) * tri.p[0] + hit.b1 * tri.p[1] + hit.b2 * tri.p[2];
    glm::vec3 q = ray.origin + hit.t * ray.dir;
    float scale = 1.0f + glm::length(ray.origin) + hit.t;
    EXPECT_NEAR(glm::length(p - q), 0.0f, 1e-4f * scale);
  }
  return hits;
}

// Inside rays start anywhere in the (slightly grown) bounds; outside rays start on a sphere
// around them and aim at a random point inside. Every third ray gets a finite t_max.
std::vector<Ray> random_rays(const Scene& scene, int n, std::uint64_t seed) {
  Rng rng(seed);
  glm::vec3 lo = scene.bounds.lo, hi = scene.bounds.hi;
  glm::vec3 centre = 0.5f * (lo + hi), extent = glm::max(hi - lo, glm::vec3(1e-3f));
  float radius = glm::length(extent);
  auto inside = [&] {
    return centre + (glm::vec3(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5f) * extent * 1.1f;
  };
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    Ray ray;
    if (i % 2 == 0) {
      ray.origin = inside();
      ray.dir = rng.direction();
    } else {
      ray.origin = centre + 1.5f * radius * rng.direction();
      ray.dir = glm::normalize(inside() - ray.origin);
    }
    ray.t_max = i % 3 == 0 ? rng.uniform(0.0f, 2.0f * radius) : INFINITY;
    rays.push_back(ray);
  }
  return rays;
}

Scene with_bounds(std::vector<SceneTriangle> tris) {
  Scene scene;
  scene.triangles = std::move(tris);
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p)
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) scene.bounds.grow(p);
  if (scene.triangles.empty()) scene.bounds.grow(glm::vec3(0.0f));
  return scene;
}

// Structure: every finite triangle appears once; leaves fit the encoding; every child box holds
// what is below it; the depth fits the traversal stack.
void check_structure(const Scene& scene, const FlatBvh& bvh) {
  ASSERT_FALSE(bvh.nodes.empty());
  std::vector<int> seen(scene.triangles.size(), 0);
  for (const BvhTriangle& t : bvh.triangles) {
    ASSERT_LT(t.triangle, scene.triangles.size());
    ++seen[t.triangle];
  }
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    bool finite = true;
    for (const glm::vec3& p : scene.triangles[i].p)
      finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    EXPECT_EQ(seen[i], finite ? 1 : 0) << "triangle " << i;
  }
  std::size_t leaf_triangles = 0;
  int max_depth = 0;
  std::function<void(std::uint32_t, int)> walk = [&](std::uint32_t index, int depth) {
    max_depth = std::max(max_depth, depth);
    const BvhNode& node = bvh.nodes.at(index);
    for (int lane = 0; lane < 4; ++lane) {
      float lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = node.bounds[(2 * a) * 4 + lane];
        hi[a] = node.bounds[(2 * a + 1) * 4 + lane];
      }
      if (lo[0] > hi[0]) continue;  // unused lane
      auto inside = [&](const float* p) {
        for (int a = 0; a < 3; ++a)
          if (p[a] < lo[a] || p[a] > hi[a]) return false;
        return true;
      };
      std::uint32_t ref = node.child[lane];
      if (ref & BVH_LEAF) {
        std::uint32_t first = (ref & ~BVH_LEAF) >> BVH_LEAF_COUNT_BITS, count = (ref & BVH_LEAF_COUNT_MASK) + 1;
        ASSERT_LE(first + count, bvh.triangles.size());
        leaf_triangles += count;
        for (std::uint32_t i = first; i < first + count; ++i) {
          const SceneTriangle& tri = scene.triangles[bvh.triangles[i].triangle];
          for (const glm::vec3& p : tri.p) EXPECT_TRUE(inside(&p.x));
        }
      } else {
        ASSERT_GT(ref, index);  // children after parents: no cycles
        const BvhNode& child = bvh.nodes.at(ref);
        for (int l = 0; l < 4; ++l) {
          float clo[3], chi[3];
          for (int a = 0; a < 3; ++a) {
            clo[a] = child.bounds[(2 * a) * 4 + l];
            chi[a] = child.bounds[(2 * a + 1) * 4 + l];
          }
          if (clo[0] <= chi[0]) {
            EXPECT_TRUE(inside(clo));
            EXPECT_TRUE(inside(chi));
          }
        }
        walk(ref, depth + 1);
      }
    }
  };
  walk(0, 1);
  EXPECT_EQ(leaf_triangles, bvh.triangles.size());
  EXPECT_LE(max_depth, BVH_MAX_NODE_DEPTH);
  EXPECT_LE(3 * max_depth + 1, BVH_STACK_SIZE);
}

void check_scene(const Scene& scene, int rays, std::uint64_t seed) {
  FlatBvh bvh = build_bvh(scene.triangles);
  check_structure(scene, bvh);
  int hits = check_rays(scene, bvh, random_rays(scene, rays, seed));
  EXPECT_GT(hits, scene.triangles.size() > 50 ? rays / 20 : 0);  // the rays do reach the geometry
}

TEST(Bvh, EmptySceneMisses) {
  FlatBvh bvh = build_bvh({});
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_TRUE(bvh.triangles.empty());
  Hit hit{};
  EXPECT_FALSE(bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), make_float3(0, 0, 0),
                               make_float3(0, 0, 1), INFINITY, &hit));
  EXPECT_FALSE(bvh_occluded(bvh.nodes.data(), bvh.triangles.data(), make_float3(0, 0, 0),
                            make_float3(0, 0, 1), INFINITY));
}

TEST(Bvh, OneTriangleExactHit) {
  Scene scene = with_bounds({{{glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)}, 0}});
  FlatBvh bvh = build_bvh(scene.triangles);
  check_structure(scene, bvh);
  Hit hit{};
  // from both sides: no culling; b1 weights p1 = (1,0,0), b2 weights p2 = (0,1,0)
  for (float side : {1.0f, -1.0f}) {
    ASSERT_TRUE(bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), make_float3(0.25f, 0.5f, 2 * side),
                                make_float3(0, 0, -side), INFINITY, &hit));
    EXPECT_FLOAT_EQ(hit.t, 2.0f);
    EXPECT_FLOAT_EQ(hit.b1, 0.25f);
    EXPECT_FLOAT_EQ(hit.b2, 0.5f);
    EXPECT_EQ(hit.triangle, 0u);
  }
  // t must lie strictly inside (0, t_max)
  EXPECT_FALSE(bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), make_float3(0.25f, 0.5f, 2),
                               make_float3(0, 0, -1), 2.0f, &hit));
  EXPECT_FALSE(bvh_occluded(bvh.nodes.data(), bvh.triangles.data(), make_float3(0.25f, 0.5f, 2),
                            make_float3(0, 0, -1), 1.5f));
  EXPECT_FALSE(bvh_occluded(bvh.nodes.data(), bvh.triangles.data(), make_float3(0.25f, 0.5f, 0),
                            make_float3(0, 0, -1), INFINITY));
  EXPECT_TRUE(bvh_occluded(bvh.nodes.data(), bvh.triangles.data(), make_float3(0.25f, 0.5f, 2),
                           make_float3(0, 0, -1), 2.5f));
  check_rays(scene, bvh, random_rays(scene, 200, 1));
}

TEST(Bvh, RandomScenesMatchBruteForce) {
  check_scene(make_random_triangles_scene(1, 7), 300, 1);
  check_scene(make_random_triangles_scene(2, 7), 300, 2);
  check_scene(make_random_triangles_scene(100, 7), 500, 3);
  check_scene(make_random_triangles_scene(10000, 7), 400, 4);
}

TEST(Bvh, RoomsSceneMatchesBruteForce) { check_scene(make_rooms_scene(3000, 3), 400, 5); }

TEST(Bvh, CoplanarTriangles) {
  // a 20 x 20 grid of squares in the plane z = 0.5, split into two triangles each
  std::vector<SceneTriangle> tris;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      glm::vec3 a(i, j, 0.5f), b(i + 1, j, 0.5f), c(i + 1, j + 1, 0.5f), d(i, j + 1, 0.5f);
      tris.push_back({{a, b, c}, 0});
      tris.push_back({{a, c, d}, 0});
    }
  Scene scene = with_bounds(tris);
  FlatBvh bvh = build_bvh(scene.triangles);
  check_structure(scene, bvh);
  check_rays(scene, bvh, random_rays(scene, 500, 6));
  // rays through grid vertices and along edges: whichever neighbour is hit, t agrees
  std::vector<Ray> grazing;
  for (int j = 0; j <= 20; j += 3)
    for (int i = 0; i <= 20; i += 2) {
      grazing.push_back({glm::vec3(i, j, 3.0f), glm::vec3(0, 0, -1), INFINITY});
      grazing.push_back({glm::vec3(i + 0.5f, j, -2.0f), glm::vec3(0, 0, 1), INFINITY});
      grazing.push_back({glm::vec3(i, j, 2.5f), glm::normalize(glm::vec3(0.3f, 0.1f, -1)), INFINITY});
      // in the plane itself: parallel to every triangle, so no hit anywhere
      grazing.push_back({glm::vec3(-1.0f, j + 0.25f, 0.5f), glm::vec3(1, 0, 0), INFINITY});
    }
  check_rays(scene, bvh, grazing);
}

TEST(Bvh, IdenticalCentroids) {
  // 200 triangles through the same centre at different angles: no split by centroid exists
  std::vector<SceneTriangle> tris;
  for (int i = 0; i < 200; ++i) {
    float a = 0.031f * i;
    glm::vec3 u(std::cos(a), std::sin(a), 0.2f * std::sin(3.0f * a)), v(-std::sin(a), std::cos(a), 0.5f);
    glm::vec3 c(1, 2, 3);
    tris.push_back({{c + u, c - u + v, c - u - v}, 0});
  }
  // and zero-area triangles stacked on one point, and ones that cannot be bounded
  for (int i = 0; i < 20; ++i) tris.push_back({{glm::vec3(1, 2, 3), glm::vec3(1, 2, 3), glm::vec3(1, 2, 3)}, 0});
  float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  tris.push_back({{glm::vec3(nan, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)}, 0});
  tris.push_back({{glm::vec3(0, 0, 0), glm::vec3(inf, 0, 0), glm::vec3(0, 1, 0)}, 0});
  Scene scene = with_bounds(tris);
  check_scene(scene, 500, 7);
}

TEST(Bvh, NestedScalesStayWithinStack) {
  // triangles of size 2^-i at 2^-i: binned SAH peels a few off per level, giving a binary tree
  // too deep to collapse greedily within the traversal stack, so the builder must fall back
  std::vector<SceneTriangle> tris;
  for (int i = 0; i < 250; ++i) {
    float x = std::ldexp(1.0f, -i);
    glm::vec3 c(x, 0.0f, 0.0f);
    tris.push_back({{c, c + glm::vec3(x, 0, 0), c + glm::vec3(0, x, x)}, 0});
  }
  check_scene(with_bounds(tris), 300, 8);
}

TEST(Bvh, AxisAlignedRaysAndBoxes) {
  // axis-aligned quads on the faces of unit cells: rays with zero direction components
  // run exactly along box faces
  std::vector<SceneTriangle> tris;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j) {
      glm::vec3 o(k, j, 0);
      tris.push_back({{o, o + glm::vec3(1, 0, 0), o + glm::vec3(1, 0, 1)}, 0});
      tris.push_back({{o, o + glm::vec3(0, 1, 0), o + glm::vec3(0, 1, 1)}, 0});
    }
  Scene scene = with_bounds(tris);
  FlatBvh bvh = build_bvh(scene.triangles);
  check_structure(scene, bvh);
  std::vector<Ray> rays;
  for (int k = 0; k <= 6; ++k)
    for (int j = 0; j <= 6; ++j) {
      rays.push_back({glm::vec3(-1, j + 0.5f, 0.5f), glm::vec3(1, 0, 0), INFINITY});
      rays.push_back({glm::vec3(k + 0.5f, -1, 0.5f), glm::vec3(0, 1, 0), INFINITY});
      rays.push_back({glm::vec3(k + 0.25f, j, 0.5f), glm::vec3(1, 0, 0), INFINITY});  // in a face's plane
      rays.push_back({glm::vec3(k, j, 2.0f), glm::vec3(0, 0, -1), INFINITY});         // down a shared edge
    }
  check_rays(scene, bvh, rays);
  check_rays(scene, bvh, random_rays(scene, 300, 9));
}

TEST(Procedural, RandomTrianglesSceneIsReproducible) {
  Scene a = make_random_triangles_scene(500, 3), b = make_random_triangles_scene(500, 3);
  ASSERT_EQ(a.triangles.size(), 500u);
  for (std::size_t i = 0; i < a.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.triangles[i].p[k], b.triangles[i].p[k]);
  EXPECT_GT(a.emissive_triangles(), 0u);
  EXPECT_GE(a.bounds.lo.x, -0.5f);
  EXPECT_LE(a.bounds.hi.x, 1.5f);
}

TEST(Procedural, RoomsSceneReachesTarget) {
  for (std::size_t target : {1000u, 20000u}) {
    Scene scene = make_rooms_scene(target, 1);
    EXPECT_GT(scene.triangles.size(), 0.9 * target);
    EXPECT_LT(scene.triangles.size(), 1.15 * target);
    EXPECT_GE(scene.emissive_triangles(), 2u);
    for (const SceneTriangle& t : scene.triangles) EXPECT_LT(t.material, scene.materials.size());
    glm::vec3 c = scene.camera.position;
    EXPECT_TRUE(c.x > scene.bounds.lo.x && c.x < scene.bounds.hi.x && c.y > scene.bounds.lo.y &&
                c.y < scene.bounds.hi.y && c.z > scene.bounds.lo.z && c.z < scene.bounds.hi.z);
  }
}

}  // namespace
}  // namespace bp

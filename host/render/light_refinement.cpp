#include "render/light_refinement.h"

#include "device/device_scene.h"
#include "passes/ray_bundles.h"
#include "scene/bundle_geometry.h"
#include "kernels/shared/bvh.h"
#include "kernels/shared/lights.h"
#include "kernels/shared/rng.h"
#include "kernels/shared/through_panes.h"
#include "scene/light_tree.h"
#include "scene/lights.h"

#include <algorithm>
#include <array>
#include <thread>
#include <vector>

namespace bp {
namespace {

constexpr bp_u32 kRefinementSeed = 0x5eed11u;  // the light samples' stream: fixed, so the layout is the scene's

double luminance(float3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }  // Rec. 709

struct TriangleScore {
  double largest_share = 0.0;
  double shadowed_area = 0.0;
};

struct Sampler {
  const Scene& scene;
  const FlatBvh& bvh;
  const LightList& lights;
  const std::vector<LightTreeNode>& tree;
  const std::vector<Material>& materials;
  float offset;
  std::uint32_t samples;

  // Over the patches of patch triangle t at subdivision k (both sides of a double-sided one): the
  // largest shadowed_share, and the sum of each patch's share times its area (m^2).
  TriangleScore score(const SceneTriangle& tri, std::size_t t, std::uint32_t k) const {
    const glm::vec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
    const glm::vec3 cross = glm::cross(e1, e2);
    TriangleScore best;
    if (!(glm::length(cross) > 0.0f)) return best;
    const double patch_area = 0.5 * double(glm::length(cross)) / double(k * k);
    const glm::vec3 normal = glm::normalize(cross);
    const glm::vec3 centroid = (tri.p[0] + tri.p[1] + tri.p[2]) / 3.0f;
    float radius = 0.0f;
    for (const glm::vec3& p : tri.p) radius = std::max(radius, glm::length(p - centroid));
    const bool two_sided = scene.materials[tri.material].double_sided;
    std::vector<double> g(std::size_t(samples) * 4);
    std::vector<std::uint8_t> v(std::size_t(samples) * 4);
    for (int side = 0; side < (two_sided ? 2 : 1); ++side) {
      const glm::vec3 n = side == 0 ? normal : -normal;
      LightReceiver receiver{};
      for (int i = 0; i < 3; ++i) {
        receiver.centroid[i] = centroid[i];
        receiver.normal[i] = n[i];
      }
      receiver.radius = radius * 1.001f + 4.0f * offset;
      receiver.light = BP_NO_LIGHT;
      receiver.infinite_visibility = 1.0f;
      const LightSet set = light_set(lights.lights.data(), lights.cdf.data(), tree.data(), &receiver,
                                     std::uint32_t(lights.lights.size()), BP_LIGHT_SELECTION_TREE);
      struct Draw {
        LightPick pick;
        float u1, u2;
      };
      std::vector<Draw> draws;
      for (std::uint32_t j = 0; j < samples; ++j) {
        Rng rng = rng_init(kRefinementSeed, std::uint32_t(t) * 2u + std::uint32_t(side), j);
        const float u_pick = rng_uniform(&rng), u1 = rng_uniform(&rng), u2 = rng_uniform(&rng);
        const LightPick pick = light_select(&set, 0u, u_pick);
        if (casts_soft_shadows(lights.lights[pick.light], centroid)) continue;  // left to the patches
        draws.push_back({pick, u1, u2});
      }
      if (draws.empty()) continue;
      for (std::uint32_t local = 0; local < k * k; ++local) {
        float b1[3], b2[3];
        patch_corner_barycentrics(local, k, b1, b2);
        glm::vec3 points[4];
        for (int c = 0; c < 3; ++c) points[c] = tri.p[0] + b1[c] * e1 + b2[c] * e2;
        points[3] = (points[0] + points[1] + points[2]) / 3.0f;
        for (int i = 0; i < 4; ++i) {
          const glm::vec3 p = points[i] + n * (4.0f * offset);
          const float3 x = make_float3(p.x, p.y, p.z);
          for (std::size_t j = 0; j < draws.size(); ++j) {
            const LightSample s = light_sample_picked(&set, materials.data(), draws[j].pick, x, draws[j].u1, draws[j].u2);
            const double cosine = double(n.x) * s.wi.x + double(n.y) * s.wi.y + double(n.z) * s.wi.z;
            const double unshadowed = cosine > 0.0 ? luminance(s.radiance_over_pdf) * cosine : 0.0;
            g[j * 4 + i] = unshadowed;
            v[j * 4 + i] = unshadowed > 0.0 && clear_through_panes(bvh, scene, x, s.wi, s.distance, offset) ? 1u : 0u;
          }
        }
        const double share = shadowed_share(g.data(), v.data(), draws.size(), 4);
        best.largest_share = std::max(best.largest_share, share);
        best.shadowed_area += share * patch_area;
      }
    }
    return best;
  }
};

}  // namespace

bool casts_soft_shadows(const Light& l, const glm::vec3& at) {
  if (l.type == BP_LIGHT_ENVIRONMENT) return true;
  if (l.type != BP_LIGHT_TRIANGLE) return false;
  const glm::vec3 p(l.position[0], l.position[1], l.position[2]);
  const glm::vec3 e1(l.edge1[0], l.edge1[1], l.edge1[2]), e2(l.edge2[0], l.edge2[1], l.edge2[2]);
  const float width = std::max({glm::length(e1), glm::length(e2), glm::length(e1 - e2)});
  return width > kSharpShadowRatio * glm::length(p + (e1 + e2) / 3.0f - at);
}

double shadowed_share(const double* unshadowed, const std::uint8_t* visible, std::size_t samples, std::size_t points) {
  double shadowed = 0.0, lit = 0.0;
  for (std::size_t j = 0; j < samples; ++j) {
    double mean = 0.0;
    std::uint8_t lo = 1, hi = 0;
    for (std::size_t i = 0; i < points; ++i) {
      mean += unshadowed[j * points + i] / double(points);
      // a point the sample cannot light (behind it) neither sees nor misses it
      if (unshadowed[j * points + i] > 0.0) {
        lo = std::min(lo, visible[j * points + i]);
        hi = std::max(hi, visible[j * points + i]);
      }
    }
    if (hi == 0) continue;
    shadowed += mean * double(hi - lo);
    lit += mean;
  }
  return lit > 0.0 ? shadowed / lit : 0.0;
}

LightRefinementOptions light_refinement_options(const Scene& scene, const PatchLayout& layout) {
  LightRefinementOptions o;
  // a patch much smaller than a bin of the buffer gets few bundles and a noisy light: none is split
  // below kMinPatchBins bins of the default buffer (the Blender room's Suzanne, 3 cm triangles
  // split to 1 cm, gave a 60-fold firefly in RB's layer)
  const BundleSize size = bundle_size(scene, layout);
  const float bin = 2.0f * size.radius / float(default_bins(size));
  o.min_patch_size = std::max(glm::length(scene.bounds.extent()) / kMinPatchFraction, kMinPatchBins * bin);
  o.max_patches = std::min(kPatchBudgetFactor * std::uint64_t(layout.patch_count), std::uint64_t(1) << 31);
  return o;
}

LightRefinementResult refine_patches_by_light(const Scene& scene, PatchLayout& layout, const FlatBvh& bvh,
                                              const LightRefinementOptions& options) {
  LightRefinementResult result;
  result.patches_before = layout.patch_count;
  LightList lights = build_light_list(scene, bvh);
  if (lights.lights.empty() || options.levels == 0 || options.light_samples == 0) return result;
  const float offset = ray_epsilon_for(scene.bounds);
  const std::vector<LightTreeNode> tree = build_light_tree(lights, scene, offset);
  const std::vector<Material> materials = pack_materials(scene, lights);
  const Sampler sampler{scene, bvh, lights, tree, materials, offset, options.light_samples};

  std::vector<std::size_t> candidates;
  for (std::size_t t = 0; t < patch_triangle_count(scene, layout); ++t)
    if (layout.subdiv[t] > 0) candidates.push_back(t);
  std::vector<bool> refined(layout.subdiv.size(), false);
  std::uint64_t total = layout.patch_count;
  for (std::uint32_t level = 0; level < options.levels && !candidates.empty(); ++level) {
    // each candidate that may still be halved, scored in parallel (each thread writes its own slots)
    std::vector<TriangleScore> scores(candidates.size());
    const std::size_t threads = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, (candidates.size() + 63) / 64);
    std::vector<std::thread> pool;
    for (std::size_t w = 0; w < threads; ++w)
      pool.emplace_back([&, w] {
        for (std::size_t c = candidates.size() * w / threads; c < candidates.size() * (w + 1) / threads; ++c) {
          const std::size_t t = candidates[c];
          const SceneTriangle& tri = patch_triangle(scene, layout, t);
          const float longest = std::max({glm::length(tri.p[1] - tri.p[0]), glm::length(tri.p[2] - tri.p[1]),
                                          glm::length(tri.p[0] - tri.p[2])});
          if (longest / float(2 * layout.subdiv[t]) < options.min_patch_size) continue;
          scores[c] = sampler.score(tri, t, layout.subdiv[t]);
        }
      });
    for (std::thread& th : pool) th.join();
    // the budget goes first where a split makes the most shadowed area per patch it adds
    auto added_by_split = [&](std::size_t t) {  // k^2 patches per side become 4 k^2
      const std::uint64_t k = layout.subdiv[t];
      return (scene.materials[patch_triangle(scene, layout, t).material].double_sided ? 2 : 1) * 3 * k * k;
    };
    std::vector<std::size_t> order;
    std::vector<double> priority(candidates.size(), 0.0);
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      if (!(scores[c].largest_share > options.split_above)) continue;
      priority[c] = scores[c].shadowed_area / double(added_by_split(candidates[c]));
      order.push_back(c);
    }
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return priority[a] > priority[b]; });
    std::vector<std::size_t> next;
    for (std::size_t c : order) {
      const std::size_t t = candidates[c];
      const std::uint64_t added = added_by_split(t);
      if (total + added > options.max_patches) {
        result.budget_reached = true;
        continue;
      }
      total += added;
      layout.subdiv[t] *= 2u;
      refined[t] = true;
      next.push_back(t);
    }
    std::sort(next.begin(), next.end());
    candidates = std::move(next);
  }
  number_patches(scene, layout);
  result.refined_triangles = std::size_t(std::count(refined.begin(), refined.end(), true));
  return result;
}

}  // namespace bp

// Binned-SAH BVH: a binary tree over triangle boxes (centroids binned on all three axes), then
// collapsed into the 4-wide nodes that kernels/shared/bvh.h walks, opening the largest child
// first (or two levels at a time where that would outgrow the traversal stack).
#include "scene/bvh.h"
#include "kernels/shared/through_panes.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <thread>

namespace bp {
namespace {

constexpr int kBins = 16;
constexpr std::uint32_t kMaxLeaf = 4;
// SAH costs of one node visit and one triangle test. A 4-wide node test costs about one
// triangle test, and the collapse removes every other binary level.
constexpr float kTraversalCost = 1.0f;
constexpr float kTriangleCost = 1.0f;
// Binary depth cap: the collapse halves it, and the traversal stack holds 3 per 4-wide level.
constexpr int kMaxBinaryDepth = 2 * BVH_MAX_NODE_DEPTH;
// Subtrees bigger than this, near the root, are built on their own thread.
constexpr std::uint32_t kParallelMin = 32 * 1024;
constexpr int kParallelDepth = 2;

// Boxes and centroids as 4-wide vectors (w unused): binning is most of the build time.
typedef float v4 __attribute__((vector_size(16)));
inline v4 vmin(v4 a, v4 b) { return a < b ? a : b; }
inline v4 vmax(v4 a, v4 b) { return a > b ? a : b; }

struct Aabb {
  v4 lo = {INFINITY, INFINITY, INFINITY, INFINITY};
  v4 hi = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
  void grow(const Aabb& b) {
    lo = vmin(lo, b.lo);
    hi = vmax(hi, b.hi);
  }
  void grow(v4 p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  float half_area() const {
    v4 e = vmax(hi - lo, v4{0, 0, 0, 0});
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  }
};

struct BuildNode {
  Aabb box;
  std::uint32_t child[2] = {0, 0};  // inner node
  std::uint32_t first = 0;          // leaf: prims order[first, first + count)
  std::uint32_t count = 0;
  bool leaf = false;
};

// Levels of median splits that take n triangles down to leaves of kMaxLeaf.
int median_levels(std::uint32_t n) {
  int levels = 0;
  for (std::uint64_t capacity = kMaxLeaf; capacity < n; capacity *= 2) ++levels;
  return levels;
}

class BinaryBuilder {
 public:
  explicit BinaryBuilder(const std::vector<SceneTriangle>& tris) {
    boxes_.reserve(tris.size());
    centroids_.reserve(tris.size());
    for (std::size_t i = 0; i < tris.size(); ++i) {
      const SceneTriangle& tri = tris[i];
      bool finite = true;
      Aabb box;
      for (const glm::vec3& p : tri.p) {
        finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        box.grow(v4{p.x, p.y, p.z, 0.0f});
      }
      if (!finite) continue;  // it could only poison the boxes; no ray can hit it
      prims_.push_back(static_cast<std::uint32_t>(i));
      boxes_.push_back(box);
      centroids_.push_back(0.5f * (box.lo + box.hi));
    }
    order_.resize(prims_.size());
    for (std::uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
  }

  // Builds the whole tree; nodes[0] is the root.
  std::vector<BuildNode> build() {
    std::vector<BuildNode> nodes;
    nodes.reserve(2 * order_.size() / kMaxLeaf + 1);
    build(nodes, 0, static_cast<std::uint32_t>(order_.size()), 0);
    return nodes;
  }

  std::size_t size() const { return order_.size(); }

  // Scene index of the prim at position i of the leaf order.
  std::uint32_t scene_index(std::uint32_t i) const { return prims_[order_[i]]; }

 private:
  struct Bin {
    Aabb box;
    std::uint32_t count = 0;
  };
  struct Split {
    int axis = -1;
    int bin = 0;        // left side: bins [0, bin)
    float cost = INFINITY;  // sum of area * count over both sides
  };

  std::uint32_t build(std::vector<BuildNode>& nodes, std::uint32_t begin, std::uint32_t end,
                      int depth) {
    std::uint32_t n = end - begin;
    Aabb box, cbox;
    for (std::uint32_t i = begin; i < end; ++i) {
      box.grow(boxes_[order_[i]]);
      cbox.grow(centroids_[order_[i]]);
    }
    std::uint32_t index = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    nodes[index].box = box;

    std::uint32_t mid = split(begin, end, depth, box, cbox);
    if (mid == begin) {
      nodes[index].leaf = true;
      nodes[index].first = begin;
      nodes[index].count = n;
      return index;
    }

    std::uint32_t left, right;
    if (depth < kParallelDepth && n >= kParallelMin) {
      std::vector<BuildNode> right_nodes;
      std::exception_ptr failure;
      std::thread worker([&] {
        try {
          right_nodes.reserve(2 * (end - mid) / kMaxLeaf + 1);
          build(right_nodes, mid, end, depth + 1);
        } catch (...) {
          failure = std::current_exception();
        }
      });
      try {
        left = build(nodes, begin, mid, depth + 1);
      } catch (...) {
        worker.join();
        throw;
      }
      worker.join();
      if (failure) std::rethrow_exception(failure);
      right = static_cast<std::uint32_t>(nodes.size());
      for (BuildNode& node : right_nodes) {
        if (!node.leaf) {
          node.child[0] += right;
          node.child[1] += right;
        }
        nodes.push_back(node);
      }
    } else {
      left = build(nodes, begin, mid, depth + 1);
      right = build(nodes, mid, end, depth + 1);
    }
    nodes[index].child[0] = left;
    nodes[index].child[1] = right;
    return index;
  }

  // Partitions order_[begin, end) and returns where the right child starts, or begin for a leaf.
  std::uint32_t split(std::uint32_t begin, std::uint32_t end, int depth, const Aabb& box,
                      const Aabb& cbox) {
    std::uint32_t n = end - begin;
    if (n <= 1) return begin;
    int axis = 0;
    float extent[3], scale[3];  // scale: centroid offset to bin index
    for (int a = 0; a < 3; ++a) {
      extent[a] = cbox.hi[a] - cbox.lo[a];
      scale[a] = extent[a] > 0.0f ? kBins * (1.0f - 1e-6f) / extent[a] : 0.0f;
      if (!std::isfinite(scale[a]) || !std::isfinite(extent[a])) extent[a] = scale[a] = 0.0f;  // denormal extent
      if (extent[a] > extent[axis]) axis = a;
    }
    bool median = extent[axis] <= 0.0f || depth + 1 + median_levels(n) > kMaxBinaryDepth;
    if (!median) {
      Split best = best_split(begin, end, cbox, scale);
      float area = box.half_area();
      float leaf_cost = kTriangleCost * static_cast<float>(n) * area;
      float split_cost = kTraversalCost * area + kTriangleCost * best.cost;
      if (n <= kMaxLeaf && leaf_cost <= split_cost) return begin;
      if (best.axis >= 0) {
        int a = best.axis;
        float lo = cbox.lo[a], s = scale[a];
        auto* mid = std::partition(order_.data() + begin, order_.data() + end, [&](std::uint32_t p) {
          return bin_of((centroids_[p][a] - lo) * s) < best.bin;
        });
        std::uint32_t m = static_cast<std::uint32_t>(mid - order_.data());
        if (m > begin && m < end) return m;
      }
    }
    if (n <= kMaxLeaf) return begin;
    // Object median along the widest centroid axis: bounded depth, and terminates when all
    // centroids coincide.
    std::uint32_t m = begin + n / 2;
    if (extent[axis] > 0.0f)
      std::nth_element(order_.data() + begin, order_.data() + m, order_.data() + end,
                       [&](std::uint32_t a, std::uint32_t b) {
                         return centroids_[a][axis] < centroids_[b][axis];
                       });
    return m;
  }

  // Bin of a scaled centroid offset; clamps in float first (rounding, and no UB converting).
  static int bin_of(float f) {
    return f > 0.0f ? static_cast<int>(f < kBins - 1 ? f : kBins - 1) : 0;
  }

  Split best_split(std::uint32_t begin, std::uint32_t end, const Aabb& cbox,
                   const float scale[3]) const {
    Bin bins[3][kBins];
    v4 scale4 = {scale[0], scale[1], scale[2], 0.0f};
    for (std::uint32_t i = begin; i < end; ++i) {
      std::uint32_t p = order_[i];
      v4 f = (centroids_[p] - cbox.lo) * scale4;  // as in split(), three axes at once
      for (int a = 0; a < 3; ++a) {
        Bin& bin = bins[a][bin_of(f[a])];
        ++bin.count;
        bin.box.grow(boxes_[p]);
      }
    }
    Split best;
    for (int a = 0; a < 3; ++a) {
      if (scale[a] <= 0.0f) continue;
      float right_cost[kBins];  // area * count of bins [b, kBins)
      Aabb right;
      std::uint32_t right_count = 0;
      for (int b = kBins - 1; b > 0; --b) {
        right.grow(bins[a][b].box);
        right_count += bins[a][b].count;
        right_cost[b] = right_count ? right.half_area() * static_cast<float>(right_count) : INFINITY;
      }
      Aabb left;
      std::uint32_t left_count = 0;
      for (int b = 1; b < kBins; ++b) {
        left.grow(bins[a][b - 1].box);
        left_count += bins[a][b - 1].count;
        if (left_count == 0) continue;
        float cost = left.half_area() * static_cast<float>(left_count) + right_cost[b];
        if (cost < best.cost) best = {a, b, cost};
      }
    }
    return best;
  }

  std::vector<std::uint32_t> prims_;     // scene index of each usable triangle
  std::vector<Aabb> boxes_;              // per prim
  std::vector<v4> centroids_;            // per prim: centre of its box
  std::vector<std::uint32_t> order_;     // prims in leaf order
};

// Collapses the binary tree two levels per node into BvhNodes, children of a node stored
// consecutively, and writes the leaves' triangles in traversal layout.
class Collapser {
 public:
  Collapser(const std::vector<BuildNode>& bin, const BinaryBuilder& builder,
            const std::vector<SceneTriangle>& tris, FlatBvh& out)
      : bin_(bin), builder_(builder), tris_(tris), out_(out) {}

  void run() {
    greedy_ = true;
    try {
      collapse();
    } catch (const DepthExceeded&) {
      greedy_ = false;  // guaranteed to fit, as the binary depth is capped
      collapse();
    }
  }

 private:
  struct DepthExceeded {};

  void collapse() {
    out_.nodes.clear();
    out_.triangles.clear();
    out_.nodes.reserve(bin_.size() / 2 + 1);
    out_.triangles.reserve(builder_.size());
    out_.nodes.push_back(empty_node());
    const BuildNode& root = bin_[0];
    if (root.leaf) {
      if (root.count > 0) set_lane(0, 0, 0);
    } else {
      fill(0, 0, 1);
    }
  }

  static BvhNode empty_node() {
    BvhNode node{};
    for (int lane = 0; lane < 4; ++lane) {
      for (int a = 0; a < 3; ++a) {
        node.bounds[(2 * a) * 4 + lane] = FLT_MAX;
        node.bounds[(2 * a + 1) * 4 + lane] = -FLT_MAX;
      }
      node.child[lane] = BVH_LEAF;
    }
    return node;
  }

  // Fills out_.nodes[index] with the children and grandchildren of binary inner node b.
  void fill(std::uint32_t index, std::uint32_t b, int depth) {
    if (depth > BVH_MAX_NODE_DEPTH) throw DepthExceeded{};
    std::uint32_t slots[4] = {bin_[b].child[0], bin_[b].child[1], 0, 0};
    int n = 2;
    if (greedy_) {
      // open the inner slot with the largest surface area until four
      while (n < 4) {
        int open = -1;
        float best_area = -1.0f;
        for (int i = 0; i < n; ++i) {
          const BuildNode& c = bin_[slots[i]];
          if (!c.leaf && c.box.half_area() > best_area) {
            best_area = c.box.half_area();
            open = i;
          }
        }
        if (open < 0) break;
        std::uint32_t opened = slots[open];
        slots[open] = bin_[opened].child[0];
        slots[n++] = bin_[opened].child[1];
      }
    } else {
      // children and grandchildren: the depth is at most half the binary depth
      n = 0;
      for (std::uint32_t c : bin_[b].child) {
        if (bin_[c].leaf) {
          slots[n++] = c;
        } else {
          slots[n++] = bin_[c].child[0];
          slots[n++] = bin_[c].child[1];
        }
      }
    }
    int inner_count = 0;
    for (int lane = 0; lane < n; ++lane) inner_count += bin_[slots[lane]].leaf ? 0 : 1;
    std::uint32_t first_child = static_cast<std::uint32_t>(out_.nodes.size());
    for (int i = 0; i < inner_count; ++i) out_.nodes.push_back(empty_node());
    int next = 0;
    for (int lane = 0; lane < n; ++lane) {
      std::uint32_t child = bin_[slots[lane]].leaf ? 0 : first_child + next++;
      set_lane(index, lane, slots[lane], child);
    }
    next = 0;
    for (int lane = 0; lane < n; ++lane)
      if (!bin_[slots[lane]].leaf) fill(first_child + next++, slots[lane], depth + 1);
  }

  // Lane `lane` of node `index` becomes binary node b: a leaf's triangles, or inner node `child`.
  void set_lane(std::uint32_t index, int lane, std::uint32_t b, std::uint32_t child = 0) {
    const BuildNode& src = bin_[b];
    BvhNode& node = out_.nodes[index];
    for (int a = 0; a < 3; ++a) {
      node.bounds[(2 * a) * 4 + lane] = src.box.lo[a] - pad(src.box.lo[a]);
      node.bounds[(2 * a + 1) * 4 + lane] = src.box.hi[a] + pad(src.box.hi[a]);
    }
    if (!src.leaf) {
      node.child[lane] = child;
      return;
    }
    std::uint32_t first = static_cast<std::uint32_t>(out_.triangles.size());
    node.child[lane] = BVH_LEAF | first << BVH_LEAF_COUNT_BITS | (src.count - 1);
    for (std::uint32_t i = src.first; i < src.first + src.count; ++i)
      out_.triangles.push_back(make_triangle(builder_.scene_index(i)));
  }

  // At least an ulp of x, and 1e-20 so that 1e-20 * (the clamped inverse direction 1e30) puts a
  // ray along a face 1e10 inside the slab (kernels/shared/bvh.h).
  static float pad(float x) { return std::max(std::fabs(x) * 1.2e-7f, 1e-20f); }

  BvhTriangle make_triangle(std::uint32_t scene_index) const {
    const SceneTriangle& tri = tris_[scene_index];
    glm::vec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
    glm::vec3 n = glm::cross(e1, e2);
    BvhTriangle t{};
    for (int a = 0; a < 3; ++a) {
      t.v0[a] = tri.p[0][a];
      t.e1[a] = e1[a];
      t.e2[a] = e2[a];
      t.n[a] = n[a];
    }
    t.triangle = scene_index;
    return t;
  }

  const std::vector<BuildNode>& bin_;
  const BinaryBuilder& builder_;
  const std::vector<SceneTriangle>& tris_;
  FlatBvh& out_;
  bool greedy_ = true;
};

}  // namespace

FlatBvh build_bvh(const std::vector<SceneTriangle>& triangles) {
  if (triangles.size() >= (std::size_t(1) << (31 - BVH_LEAF_COUNT_BITS)))
    throw std::invalid_argument("bvh: too many triangles for the leaf encoding");
  BinaryBuilder builder(triangles);
  std::vector<BuildNode> binary = builder.build();
  FlatBvh flat;
  Collapser(binary, builder, triangles, flat).run();
  return flat;
}

bool clear_through_panes(const FlatBvh& bvh, const Scene& scene, float3 origin, float3 dir, float distance,
                         float step) {
  const float t_max = distance < BP_FLOAT_MAX ? distance - step : BP_FLOAT_MAX;
  if (!scene.has_transmission()) return !bvh_occluded(bvh.nodes.data(), bvh.triangles.data(), origin, dir, t_max);
  float travelled = 0.0f;
  for (std::uint32_t k = 0; k <= BP_MAX_PANE_CROSSINGS; ++k) {
    Hit hit;
    const float left = t_max < BP_FLOAT_MAX ? t_max - travelled : BP_FLOAT_MAX;
    if (!(left > 0.0f) || !bvh_closest_hit(bvh.nodes.data(), bvh.triangles.data(), origin, dir, left, &hit)) return true;
    if (!(scene.materials[scene.triangles[hit.triangle].material].transmission > 0.0f)) return false;
    origin = origin + dir * (hit.t + step);
    travelled += hit.t + step;
  }
  return false;
}

}  // namespace bp

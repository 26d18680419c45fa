#include "scene/light_tree.h"
#include "kernels/shared/through_panes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace bp {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kBins = 12;
constexpr std::size_t kMaxLeafLights = 8;

// A cone of directions: every direction within theta of axis (theta >= pi: all of them).
struct Cone {
  glm::dvec3 axis{0.0, 0.0, 1.0};
  double theta = -1.0;  // < 0: empty
  bool empty() const { return theta < 0.0; }
};

Cone cone_union(const Cone& a, const Cone& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  if (a.theta >= kPi || b.theta >= kPi) return Cone{a.axis, kPi};
  const double between = std::acos(std::clamp(glm::dot(a.axis, b.axis), -1.0, 1.0));
  if (between + b.theta <= a.theta) return a;
  if (between + a.theta <= b.theta) return b;
  const double theta = 0.5 * (a.theta + between + b.theta);
  const glm::dvec3 turn = glm::cross(a.axis, b.axis);
  if (theta >= kPi || glm::length(turn) < 1e-9) return Cone{a.axis, kPi};
  // a's axis turned towards b's by theta - theta_a, about their common perpendicular.
  const glm::dvec3 k = glm::normalize(turn), v = a.axis;
  const double phi = theta - a.theta;
  const glm::dvec3 axis = v * std::cos(phi) + glm::cross(k, v) * std::sin(phi) + k * glm::dot(k, v) * (1.0 - std::cos(phi));
  return Cone{glm::normalize(axis), theta};
}

// What a node bounds: position, normals, the emission spread about them, power.
struct LightBounds {
  glm::dvec3 lo{1e300}, hi{-1e300};
  Cone normals;
  double theta_e = 0.0;
  double power = 0.0;
  bool two_sided = false;

  void grow(const LightBounds& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
    normals = cone_union(normals, b.normals);
    theta_e = std::max(theta_e, b.theta_e);
    power += b.power;
    two_sided = two_sided || b.two_sided;
  }
  glm::dvec3 centroid() const { return 0.5 * (lo + hi); }
  double surface_area() const {
    const glm::dvec3 e = glm::max(hi - lo, glm::dvec3(0.0));
    return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

// Conty & Kulla's orientation measure: the solid angle a cone of normals (theta_o) with emission
// spread theta_e can light, weighted by cosine.
double orientation_measure(double theta_o, double theta_e) {
  theta_o = std::min(theta_o, kPi);
  const double theta_w = std::min(theta_o + theta_e, kPi), sin_o = std::sin(theta_o), cos_o = std::cos(theta_o);
  return 2.0 * kPi * (1.0 - cos_o) +
         0.5 * kPi * (2.0 * theta_w * sin_o - std::cos(theta_o - 2.0 * theta_w) - 2.0 * theta_o * sin_o + cos_o);
}

// The split cost of one side: power x orientation measure x surface area (a point's area counts as a
// tiny one so that point lights still prefer compact groups), stretched along thin axes.
double split_cost(const LightBounds& b, double stretch) {
  const glm::dvec3 e = b.hi - b.lo;
  const double size = std::max({e.x, e.y, e.z, 1e-30});
  return b.power * orientation_measure(std::max(b.normals.theta, 0.0), b.theta_e) *
         (b.surface_area() + 1e-6 * size * size + 1e-30) * stretch;
}

LightBounds bounds_of(const Light& l, bool double_sided) {
  LightBounds b;
  const glm::dvec3 p(l.position[0], l.position[1], l.position[2]), axis(l.axis[0], l.axis[1], l.axis[2]);
  b.lo = b.hi = p;
  b.power = double(l.select_probability);
  if (l.type == BP_LIGHT_TRIANGLE) {
    for (const float* e : {l.edge1, l.edge2}) {
      const glm::dvec3 q = p + glm::dvec3(e[0], e[1], e[2]);
      b.lo = glm::min(b.lo, q);
      b.hi = glm::max(b.hi, q);
    }
    b.normals = Cone{glm::length(axis) > 0.0 ? glm::normalize(axis) : glm::dvec3(0, 0, 1), 0.0};
    b.theta_e = 0.5 * kPi;
    b.two_sided = double_sided;
  } else if (l.type == BP_LIGHT_SPOT) {
    b.normals = Cone{glm::normalize(axis), 0.0};
    b.theta_e = std::acos(std::clamp(double(l.cos_outer), -1.0, 1.0));
  } else {
    b.normals = Cone{glm::dvec3(0, 0, 1), kPi};  // a point light shines everywhere
    b.theta_e = 0.5 * kPi;
  }
  return b;
}

struct Builder {
  LightList& list;
  std::vector<LightBounds> light_bounds;
  std::vector<std::uint32_t> order;  // light indices, partitioned as the tree is built
  std::vector<LightTreeNode> nodes;

  static void store(float* out, const glm::dvec3& v) {
    for (int i = 0; i < 3; ++i) out[i] = float(v[i]);
  }

  // Node bounds in float, rounded outwards so they hold what they bound.
  static void store_node(LightTreeNode& n, const LightBounds& b) {
    for (int i = 0; i < 3; ++i) {
      n.lo[i] = std::nextafter(float(b.lo[i]), -INFINITY);
      n.hi[i] = std::nextafter(float(b.hi[i]), INFINITY);
    }
    n.power = float(b.power);
    store(n.axis, b.normals.axis);
    const double theta_o = b.normals.theta + 1e-6, theta_e = b.theta_e + 1e-6;  // rounding, outwards
    n.cos_theta_o = theta_o >= kPi ? -1.0f : float(std::cos(theta_o));
    n.cos_theta_e = theta_e >= kPi ? -1.0f : float(std::cos(theta_e));
    n.flags = b.two_sided ? BP_LIGHT_NODE_TWO_SIDED : 0u;
  }

  // Index in `order` where [begin, end) splits; the halves are partitioned in place.
  std::size_t split(std::size_t begin, std::size_t end, const LightBounds& all, bool balanced) {
    glm::dvec3 clo(1e300), chi(-1e300);
    for (std::size_t i = begin; i < end; ++i) {
      const glm::dvec3 c = light_bounds[order[i]].centroid();
      clo = glm::min(clo, c);
      chi = glm::max(chi, c);
    }
    const glm::dvec3 extent = chi - clo, box = all.hi - all.lo;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    auto by_axis = [&](int a) {
      return [&, a](std::uint32_t x, std::uint32_t y) {
        return light_bounds[x].centroid()[a] < light_bounds[y].centroid()[a];
      };
    };
    const std::size_t middle = begin + (end - begin) / 2;
    if (balanced || !(extent[axis] > 0.0)) {
      std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, by_axis(axis));
      return middle;
    }
    double best_cost = INFINITY;
    int best_axis = -1, best_bin = -1;
    const double max_box = std::max({box.x, box.y, box.z});
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0)) continue;
      std::array<LightBounds, kBins> bins{};
      auto bin_of = [&](std::uint32_t l) {
        return std::clamp(int(kBins * (light_bounds[l].centroid()[a] - clo[a]) / extent[a]), 0, kBins - 1);
      };
      for (std::size_t i = begin; i < end; ++i) bins[bin_of(order[i])].grow(light_bounds[order[i]]);
      std::array<LightBounds, kBins> below{};  // below[k]: bins 0..k
      LightBounds run;
      for (int k = 0; k < kBins; ++k) {
        run.grow(bins[k]);
        below[k] = run;
      }
      const double stretch = max_box / std::max(box[a], 1e-30 * max_box + 1e-300);
      LightBounds above;
      for (int k = kBins - 1; k >= 1; --k) {
        above.grow(bins[k]);
        if (above.lo.x > above.hi.x) continue;                       // nothing above yet
        if (below[k - 1].lo.x > below[k - 1].hi.x) continue;           // nothing below
        const double cost = split_cost(below[k - 1], stretch) + split_cost(above, stretch);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = a;
          best_bin = k;
        }
      }
    }
    if (best_axis < 0) {
      std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, by_axis(axis));
      return middle;
    }
    const double lo = clo[best_axis], ext = extent[best_axis];
    auto first = std::partition(order.begin() + begin, order.begin() + end, [&](std::uint32_t l) {
      return std::clamp(int(kBins * (light_bounds[l].centroid()[best_axis] - lo) / ext), 0, kBins - 1) < best_bin;
    });
    const std::size_t at = std::size_t(first - order.begin());
    if (at == begin || at == end) {  // every centroid in one bin (rounding): halve instead
      std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, by_axis(best_axis));
      return middle;
    }
    return at;
  }

  // Whether order[begin, end) is one panel: a few triangles of one material facing one way, as
  // compact as a square of their area. Such a leaf's lights are chosen by power: a tree below it
  // would cost importance evaluations and gain next to nothing.
  bool is_panel(std::size_t begin, std::size_t end, const LightBounds& all) const {
    if (end - begin == 1) return true;
    if (end - begin > kMaxLeafLights || all.normals.theta > 1e-3) return false;
    const std::uint32_t material = list.lights[order[begin]].material;
    double area = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
      const Light& l = list.lights[order[i]];
      if (l.type != BP_LIGHT_TRIANGLE || l.material != material) return false;
      area += double(l.area);
    }
    return glm::length(all.hi - all.lo) <= 2.0 * std::sqrt(area);
  }

  // Builds the subtree of order[begin, end) at nodes.size(); returns its index.
  std::uint32_t build(std::size_t begin, std::size_t end, std::uint32_t depth, std::uint64_t trail) {
    const std::uint32_t index = std::uint32_t(nodes.size());
    nodes.emplace_back();
    LightBounds all;
    for (std::size_t i = begin; i < end; ++i) all.grow(light_bounds[order[i]]);
    if (is_panel(begin, end, all)) {
      LightTreeNode& leaf = nodes[index];
      store_node(leaf, all);
      leaf.flags |= BP_LIGHT_NODE_LEAF;
      leaf.child = std::uint32_t(begin);  // lights are renumbered in tree order at the end
      leaf.leaf_lights = std::uint32_t(end - begin);
      for (std::size_t i = begin; i < end; ++i) {
        Light& l = list.lights[order[i]];
        l.tree_trail[0] = std::uint32_t(trail);
        l.tree_trail[1] = std::uint32_t(trail >> 32);
        l.tree_depth = depth;
      }
      return index;
    }
    // Balanced splits once the depth budget (64 trail bits) could run out.
    const std::uint32_t levels_needed = std::uint32_t(std::ceil(std::log2(double(end - begin))));
    const std::size_t at = split(begin, end, all, depth + levels_needed >= 56);
    build(begin, at, depth + 1, trail);
    const std::uint32_t second = build(at, end, depth + 1, trail | (std::uint64_t(1) << depth));
    store_node(nodes[index], all);
    nodes[index].child = second;
    return index;
  }
};

}  // namespace

std::vector<LightTreeNode> build_light_tree(LightList& lights, const Scene& scene, float offset) {
  Builder b{lights, {}, {}, {}};
  // Directional lights and the environment (last in the list) have no place: light selection picks them outside the
  // tree, by power (kernels/shared/lights.h); the tree holds the others.
  const std::size_t all = lights.lights.size();
  std::size_t n = 0;
  while (n < all && !light_is_infinite(lights.lights[n].type)) ++n;
  if (n == 0) return {};
  b.light_bounds.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Light& l = lights.lights[k];
    b.light_bounds.push_back(bounds_of(l, l.type == BP_LIGHT_TRIANGLE && scene.materials[l.material].double_sided));
  }
  b.order.resize(n);
  std::iota(b.order.begin(), b.order.end(), 0u);
  b.nodes.reserve(2 * n);
  b.build(0, n, 0, 0);
  for (LightTreeNode& node : b.nodes) node.receiver_offset = offset;
  // Renumber the lights in tree order, so that a leaf's lights are consecutive.
  std::vector<Light> renumbered(lights.lights);
  std::vector<std::uint32_t> new_index(n);
  for (std::size_t k = 0; k < n; ++k) {
    renumbered[k] = lights.lights[b.order[k]];
    new_index[b.order[k]] = std::uint32_t(k);
  }
  lights.lights = std::move(renumbered);
  for (std::uint32_t& l : lights.light_of_triangle)
    if (l != BP_NO_LIGHT) l = new_index[l];
  double running = 0.0;
  for (std::size_t k = 0; k < all; ++k) {
    running += double(lights.lights[k].select_probability);
    lights.cdf[k] = k + 1 == all ? 1.0f : float(running);
  }
  return b.nodes;
}

namespace {

// The points of infinite_visibility: a stratified (0, 2)-sequence in the unit square (x by rank,
// y its base-2 radical inverse), mapped onto the patch or to cosine-distributed directions.
glm::dvec2 visibility_point(int j) {
  std::uint32_t bits = std::uint32_t(j), reversed = 0;
  for (int b = 0; b < 4; ++b, bits >>= 1) reversed = reversed << 1 | (bits & 1u);  // kVisibilityRays = 2^4
  return {(j + 0.5) / kVisibilityRays, (reversed + 0.5) / kVisibilityRays};
}

// How much of the infinite lights reaches a patch with corners c and unit normal n: per light, the
// share of kVisibilityRays rays from points spread over the patch (offset along n) that leave the
// scene -- towards a sun, or along cosine-distributed directions for the environment -- averaged
// with the lights' power shares, at least 1 / kVisibilityRays.
float infinite_visibility(const glm::dvec3 c[3], const glm::dvec3& n, const LightList& lights, const FlatBvh& bvh,
                          const Scene& scene, float offset) {
  double seen = 0.0, share = 0.0;
  const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 t = glm::normalize(glm::cross(n, helper)), b = glm::cross(n, t);
  for (const Light& l : lights.lights) {
    if (l.type != BP_LIGHT_DIRECTIONAL && l.type != BP_LIGHT_ENVIRONMENT) continue;
    const glm::dvec3 to_sun = -glm::dvec3(l.axis[0], l.axis[1], l.axis[2]);
    const bool faces = l.type != BP_LIGHT_DIRECTIONAL || glm::dot(n, to_sun) > 0.0;  // a sun behind it: none
    int escaped = 0;
    for (int j = 0; faces && j < kVisibilityRays; ++j) {
      const glm::dvec2 u = visibility_point(j);
      const double root = std::sqrt(u.x);  // uniform on the triangle, and cosine about n (Malley)
      const glm::dvec3 p = c[0] * (1.0 - root) + c[1] * (root * (1.0 - u.y)) + c[2] * (root * u.y) + n * (4.0 * offset);
      const double phi = 2.0 * kPi * u.y;
      const glm::dvec3 dir = l.type == BP_LIGHT_DIRECTIONAL
                                 ? to_sun
                                 : t * (root * std::cos(phi)) + b * (root * std::sin(phi)) + n * std::sqrt(1.0 - u.x);
      escaped += clear_through_panes(bvh, scene, make_float3(float(p.x), float(p.y), float(p.z)),
                                     make_float3(float(dir.x), float(dir.y), float(dir.z)), BP_FLOAT_MAX, offset);
    }
    seen += double(l.select_probability) * escaped / kVisibilityRays;
    share += double(l.select_probability);
  }
  return share > 0.0 ? float(std::max(seen / share, 1.0 / kVisibilityRays)) : 1.0f;
}

}  // namespace

std::vector<LightReceiver> build_light_receivers(const Scene& scene, const PatchLayout& patches,
                                                 const LightList& lights, float offset, const FlatBvh* bvh) {
  std::vector<LightReceiver> out(patches.patch_count);
  const bool infinite = !lights.lights.empty() && light_is_infinite(lights.lights.back().type);
  for_each_sub_triangle_in_parallel(scene, patches, [&](const SubTriangle& sub) {
    const SceneTriangle& tri = *sub.parent;
    const std::uint32_t light = lights.light_of_triangle.empty() || sub.triangle >= scene.triangles.size()
                                    ? BP_NO_LIGHT  // (a cluster's fan: clusters emit nothing)
                                    : lights.light_of_triangle[sub.triangle];
    glm::dvec3 c[3], centroid(0.0);
    for (int i = 0; i < 3; ++i) {
      c[i] = glm::dvec3(tri.p[0]) + double(sub.b1[i]) * glm::dvec3(sub.e1) + double(sub.b2[i]) * glm::dvec3(sub.e2);
      centroid += c[i] / 3.0;
    }
    double radius = 0.0;
    for (int i = 0; i < 3; ++i) radius = std::max(radius, glm::length(c[i] - centroid));
    // Grown for the float rounding of hit points and patch indices, and the rays' offset.
    const float r = float(radius * 1.001 + 1e-6 * glm::length(centroid)) + 4.0f * offset;
    for (std::uint32_t side = 0; side < (sub.double_sided ? 2u : 1u); ++side) {
      LightReceiver& rec = out[patches.first_patch[sub.triangle] + side * sub.k2 + sub.local];
      rec = LightReceiver{};
      for (int i = 0; i < 3; ++i) {
        rec.centroid[i] = float(centroid[i]);
        rec.normal[i] = side == 0 ? sub.normal[i] : -sub.normal[i];
      }
      rec.radius = r;
      rec.light = light;
      rec.infinite_visibility =
          infinite && bvh ? infinite_visibility(c, glm::dvec3(side == 0 ? sub.normal : -sub.normal), lights, *bvh, scene, offset)
                          : 1.0f;
    }
  });
  return out;
}

}  // namespace bp

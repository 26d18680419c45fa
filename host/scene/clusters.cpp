#include "scene/clusters.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace bp {
namespace {

constexpr double kCoplanarNormalCos = 1.0 - 5e-7;  // normals within about 0.06 degrees
constexpr double kCoplanarDistance = 1e-5;         // corners off the plane, of the scene's diagonal
constexpr double kConvexAreaSlack = 1e-5;          // hull area over the triangles' summed area

glm::dvec3 flat_normal(const SceneTriangle& t) {
  const glm::dvec3 c = glm::cross(glm::dvec3(t.p[1] - t.p[0]), glm::dvec3(t.p[2] - t.p[0]));
  const double len = glm::length(c);
  return len > 0.0 ? c / len : glm::dvec3(0.0);
}

// Corners welded where their positions are bit-identical: a corner id per triangle corner.
std::vector<std::uint32_t> weld_corners(const Scene& scene) {
  struct Corner {
    std::uint32_t bits[3];
    std::uint32_t index;
  };
  std::vector<Corner> corners(3 * scene.triangles.size());
  for (std::size_t t = 0; t < scene.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      Corner& k = corners[3 * t + c];
      std::memcpy(k.bits, &scene.triangles[t].p[c][0], sizeof(k.bits));
      for (std::uint32_t& b : k.bits)
        if (b == 0x80000000u) b = 0u;  // -0 is +0
      k.index = std::uint32_t(3 * t + c);
    }
  std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
    return std::lexicographical_compare(a.bits, a.bits + 3, b.bits, b.bits + 3);
  });
  std::vector<std::uint32_t> id(corners.size());
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (i > 0 && !std::equal(corners[i].bits, corners[i].bits + 3, corners[i - 1].bits)) ++next;
    id[corners[i].index] = next;
  }
  return id;
}

// Triangles across each shared edge, as CSR: neighbours of t are adjacent[start[t] .. start[t + 1]).
struct Adjacency {
  std::vector<std::uint32_t> start, adjacent;
};

Adjacency edge_adjacency(const Scene& scene) {
  const std::vector<std::uint32_t> corner = weld_corners(scene);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
  edges.reserve(corner.size());
  for (std::size_t t = 0; t < scene.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      std::uint64_t a = corner[3 * t + c], b = corner[3 * t + (c + 1) % 3];
      if (a == b) continue;
      edges.emplace_back(std::min(a, b) << 32 | std::max(a, b), std::uint32_t(t));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (std::size_t a = i; a < j; ++a)
      for (std::size_t b = i; b < j; ++b)
        if (edges[a].second != edges[b].second) pairs.emplace_back(edges[a].second, edges[b].second);
    i = j;
  }
  Adjacency adj;
  adj.start.assign(scene.triangles.size() + 1, 0u);
  for (const auto& p : pairs) ++adj.start[p.first + 1];
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) adj.start[t + 1] += adj.start[t];
  adj.adjacent.resize(pairs.size());
  std::vector<std::uint32_t> cursor(adj.start.begin(), adj.start.end() - 1);
  for (const auto& p : pairs) adj.adjacent[cursor[p.first]++] = p.second;
  return adj;
}

struct HullPoint {
  double x, y;     // in the cluster's plane
  glm::vec3 p;     // the scene's corner
};

// Convex hull, counter-clockwise (Andrew's monotone chain); corners within `collinear` (a cross
// product, m^2) of the line through their neighbours are dropped.
std::vector<HullPoint> convex_hull(std::vector<HullPoint> pts, double collinear) {
  std::sort(pts.begin(), pts.end(), [](const HullPoint& a, const HullPoint& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  auto cross = [](const HullPoint& o, const HullPoint& a, const HullPoint& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<HullPoint> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= collinear) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= collinear) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

double polygon_area(const std::vector<HullPoint>& h) {
  double twice = 0.0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const HullPoint &a = h[i], &b = h[(i + 1) % h.size()];
    twice += a.x * b.y - b.x * a.y;
  }
  return 0.5 * twice;
}

// Strictly inside a counter-clockwise polygon (by more than `margin`, a cross product in m^2).
bool inside(const std::vector<HullPoint>& h, const HullPoint& q, double margin) {
  if (h.size() < 3) return false;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const HullPoint &a = h[i], &b = h[(i + 1) % h.size()];
    if ((b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x) <= margin) return false;
  }
  return true;
}

double diameter(const std::vector<HullPoint>& h) {
  double d2 = 0.0;
  for (std::size_t i = 0; i < h.size(); ++i)
    for (std::size_t j = i + 1; j < h.size(); ++j)
      d2 = std::max(d2, (h[i].x - h[j].x) * (h[i].x - h[j].x) + (h[i].y - h[j].y) * (h[i].y - h[j].y));
  return std::sqrt(d2);
}

// One cluster being grown: its plane, outline and the summed area of its triangles.
struct Growing {
  std::uint32_t material;
  glm::dvec3 origin, normal, u, v;
  std::vector<HullPoint> hull;
  double area = 0.0;
  std::vector<std::uint32_t> members;

  HullPoint in_plane(const glm::vec3& p) const {
    const glm::dvec3 d = glm::dvec3(p) - origin;
    return {glm::dot(d, u), glm::dot(d, v), p};
  }
};

}  // namespace

bool clusterable_triangle(const Scene& scene, std::size_t t) {
  const SceneTriangle& tri = scene.triangles[t];
  const SceneMaterial& m = scene.materials[tri.material];
  if (m.emission != glm::vec3(0.0f) || m.textured() || m.has_normal_map() || m.transmission > 0.0f ||
      m.textures.alpha_cutoff > 0.0f)
    return false;
  const glm::dvec3 n = flat_normal(tri);
  if (n == glm::dvec3(0.0)) return false;
  if (tri.has_normals)
    for (const glm::vec3& c : tri.normal)
      if (glm::dot(glm::dvec3(c), n) < kCoplanarNormalCos) return false;
  return true;
}

PatchClusters build_patch_clusters(const Scene& scene, float max_size) {
  const std::size_t n = scene.triangles.size();
  PatchClusters out;
  out.fan_first.assign(n, 0u);
  out.fan_count.assign(n, 0u);
  const Adjacency adj = edge_adjacency(scene);
  std::vector<char> clusterable(n);
  for (std::size_t t = 0; t < n; ++t) clusterable[t] = clusterable_triangle(scene, t);
  std::vector<char> clustered(n, 0);
  std::vector<std::uint32_t> seen(n, UINT32_MAX);  // the seed whose growth queued the triangle
  const double diagonal = glm::length(glm::dvec3(scene.bounds.extent()));
  const double plane_distance = kCoplanarDistance * diagonal;
  const double collinear = 1e-6 * double(max_size) * double(max_size);

  constexpr std::uint32_t kNone = UINT32_MAX;
  std::vector<std::uint32_t> member(n, kNone), barred(n, kNone);  // the seed whose cluster holds / bars it
  for (std::uint32_t seed = 0; seed < n; ++seed) {
    if (clustered[seed] || !clusterable[seed]) continue;
    const SceneTriangle& s = scene.triangles[seed];
    Growing g;
    g.material = s.material;
    g.origin = glm::dvec3(s.p[0]);
    g.normal = flat_normal(s);
    g.u = glm::normalize(glm::dvec3(s.p[1] - s.p[0]));
    g.v = glm::cross(g.normal, g.u);
    auto in_the_plane = [&](std::uint32_t t) {
      const SceneTriangle& tri = scene.triangles[t];
      if (tri.material != g.material || glm::dot(flat_normal(tri), g.normal) < kCoplanarNormalCos) return false;
      for (const glm::vec3& p : tri.p)
        if (std::abs(glm::dot(glm::dvec3(p) - g.origin, g.normal)) > plane_distance) return false;
      return true;
    };
    std::vector<std::uint32_t> frontier;
    auto join = [&](std::uint32_t t, std::vector<HullPoint> hull, double area) {
      g.hull = std::move(hull);
      g.area = area;
      g.members.push_back(t);
      member[t] = seed;
      for (std::uint32_t i = adj.start[t]; i < adj.start[t + 1]; ++i) {
        const std::uint32_t nb = adj.adjacent[i];
        if (seen[nb] != seed && !clustered[nb] && clusterable[nb] && in_the_plane(nb)) {
          seen[nb] = seed;
          frontier.push_back(nb);
        }
      }
    };
    auto triangle_area = [&](std::uint32_t t) {
      const SceneTriangle& tri = scene.triangles[t];
      return 0.5 * glm::length(glm::cross(glm::dvec3(tri.p[1] - tri.p[0]), glm::dvec3(tri.p[2] - tri.p[0])));
    };
    // the hull with t, if it keeps the corner and diameter caps
    auto grown_hull = [&](std::uint32_t t, std::vector<HullPoint>& hull) {
      std::vector<HullPoint> pts = g.hull;
      for (const glm::vec3& p : scene.triangles[t].p) pts.push_back(g.in_plane(p));
      hull = convex_hull(std::move(pts), collinear);
      return hull.size() >= 3 && hull.size() <= kMaxClusterCorners && diameter(hull) <= double(max_size);
    };
    {
      std::vector<HullPoint> hull;
      seen[seed] = seed;
      if (!grown_hull(seed, hull)) continue;
      join(seed, std::move(hull), triangle_area(seed));
    }
    // Growth: from a convex union (its hull) any neighbour may start an excursion; while the union is
    // not convex only a triangle within the hull (filling it) or reaching into it joins. A convex state
    // is kept; an excursion that cannot return to one is undone and its triangles barred, so a grid
    // grows by whole rows and columns into rectangles.
    struct Convex {
      std::size_t members;
      std::vector<HullPoint> hull;
      double area;
    } kept{1, g.hull, g.area};
    std::vector<std::uint32_t> near;  // not convex: the last joined triangle's candidate neighbours, tried first
    for (;;) {
      const bool convex = polygon_area(g.hull) <= g.area * (1.0 + kConvexAreaSlack);
      if (convex) {
        kept = {g.members.size(), g.hull, g.area};
        std::erase_if(frontier, [&](std::uint32_t t) { return member[t] == seed || barred[t] == seed; });
      }
      near.clear();
      if (!convex)
        for (std::uint32_t i = adj.start[g.members.back()]; i < adj.start[g.members.back() + 1]; ++i)
          near.push_back(adj.adjacent[i]);
      bool joined = false;
      for (std::size_t pass = 0; pass < 4 && !joined; ++pass) {  // (not convex: fills first, then reaches)
        for (std::uint32_t t : pass < 2 ? near : frontier) {
          if (seen[t] != seed || member[t] == seed || barred[t] == seed) continue;  // not a candidate (now)
          int within = 0, strictly = 0;  // corners inside or on the hull, strictly inside
          for (const glm::vec3& p : scene.triangles[t].p) {
            const HullPoint q = g.in_plane(p);
            within += inside(g.hull, q, -collinear);
            strictly += inside(g.hull, q, collinear);
          }
          std::vector<HullPoint> hull;
          if (convex) {
            if (strictly > 0 || !grown_hull(t, hull)) {  // overlapping, or past the caps
              barred[t] = seed;
              continue;
            }
          } else if (pass % 2 == 0) {
            if (within < 3) continue;
            hull = g.hull;
            if (g.area + triangle_area(t) > polygon_area(hull) * (1.0 + kConvexAreaSlack)) {  // overlapping
              barred[t] = seed;
              continue;
            }
          } else if (strictly == 0 || !grown_hull(t, hull)) {
            continue;
          }
          join(t, std::move(hull), g.area + triangle_area(t));
          joined = true;
          break;
        }
        if (convex && pass >= 2) break;
      }
      if (joined) continue;
      if (convex) break;
      // undo, barring the excursion's triangles (another excursion through them would end the same
      // way, and retrying each would make a side's failure quadratic)
      for (std::size_t i = kept.members; i < g.members.size(); ++i) {
        member[g.members[i]] = kNone;
        barred[g.members[i]] = seed;
      }
      g.members.resize(kept.members);
      g.hull = kept.hull;
      g.area = kept.area;
    }
    if (g.members.size() < 2) continue;
    const std::uint32_t first = std::uint32_t(out.fans.size()), count = std::uint32_t(g.hull.size() - 2);
    for (std::uint32_t i = 1; i + 1 < g.hull.size(); ++i) {
      SceneTriangle f{};
      f.p[0] = g.hull[0].p;
      f.p[1] = g.hull[i].p;
      f.p[2] = g.hull[i + 1].p;
      f.material = g.material;
      out.fans.push_back(f);
      out.fan_source.push_back(seed);
    }
    for (std::uint32_t t : g.members) {
      clustered[t] = 1;
      out.fan_first[t] = first;
      out.fan_count[t] = count;
    }
    ++out.clusters;
    out.clustered_triangles += g.members.size();
  }
  return out;
}

}  // namespace bp

// Independent reference path tracer (see reference_renderer.h). Deliberately simple: double
// precision everywhere, a median-split BVH, uniform hemisphere sampling, fixed Russian roulette.
#include "e2e/reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace bp {

using glm::dvec3;
constexpr double kPi = std::numbers::pi;

namespace reference_detail {

glm::dvec3 phong_brdf(const SceneMaterial& material, const dvec3& normal, const dvec3& wo, const dvec3& wi) {
  const double cos_o = glm::dot(normal, wo), cos_i = glm::dot(normal, wi);
  if (cos_o <= 0.0 || cos_i <= 0.0) return dvec3(0.0);
  const dvec3 mirror_of_wo = 2.0 * cos_o * normal - wo;
  const double cos_alpha = glm::dot(wi, mirror_of_wo);
  const double n = material.shininess;
  const double lobe = cos_alpha > 0.0 ? (n + 2.0) / (2.0 * kPi) * std::pow(cos_alpha, n) : 0.0;
  return dvec3(material.kd) / kPi + dvec3(material.ks) * lobe;
}

}  // namespace reference_detail

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr int kRouletteFromDepth = 3;      // bounces before Russian roulette starts
constexpr double kRouletteSurvival = 0.8;  // fixed survival probability after that
constexpr int kMaxDepth = 1000;            // safety net only: 0.8^997 is nothing

struct Triangle {
  dvec3 p0, e1, e2;  // p = p0 + u e1 + v e2
  dvec3 normal;      // unit, counter-clockwise = front
  double area;
  std::uint32_t material;
};

struct Hit {
  double t = std::numeric_limits<double>::infinity();
  std::uint32_t triangle = kNone;
  double u = 0.0, v = 0.0;
};

// Möller–Trumbore, both sides; updates hit when closer than hit.t and farther than t_min.
bool intersect(const Triangle& tri, const dvec3& origin, const dvec3& dir, double t_min, Hit& hit,
               std::uint32_t index) {
  const dvec3 p = glm::cross(dir, tri.e2);
  const double det = glm::dot(tri.e1, p);
  if (det == 0.0) return false;
  const double inv_det = 1.0 / det;
  const dvec3 s = origin - tri.p0;
  const double u = glm::dot(s, p) * inv_det;
  if (u < 0.0 || u > 1.0) return false;
  const dvec3 q = glm::cross(s, tri.e1);
  const double v = glm::dot(dir, q) * inv_det;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = glm::dot(tri.e2, q) * inv_det;
  if (!(t > t_min && t < hit.t)) return false;
  hit = {t, index, u, v};
  return true;
}

// Median split on the longest centroid axis; leaves of at most 4 triangles.
class Bvh {
 public:
  Bvh() = default;
  explicit Bvh(const std::vector<Triangle>& triangles) : triangles_(&triangles) {
    order_.resize(triangles.size());
    for (std::uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
    if (!order_.empty()) build(0, std::uint32_t(order_.size()));
  }

  Hit closest(const dvec3& origin, const dvec3& dir, std::uint32_t skip, double t_min) const {
    Hit hit;
    traverse(origin, dir, [&](std::uint32_t i) {
      if (i != skip) intersect((*triangles_)[i], origin, dir, t_min, hit, i);
      return false;
    }, hit.t);
    return hit;
  }

  // Any hit with t_min < t < t_max, ignoring two triangles (the ends of the segment).
  bool occluded(const dvec3& origin, const dvec3& dir, double t_min, double t_max, std::uint32_t skip_a,
                std::uint32_t skip_b) const {
    Hit hit;
    hit.t = t_max;
    return traverse(origin, dir, [&](std::uint32_t i) {
      return i != skip_a && i != skip_b && intersect((*triangles_)[i], origin, dir, t_min, hit, i);
    }, hit.t);
  }

 private:
  struct Node {
    dvec3 lo, hi;
    std::uint32_t first = 0, count = 0;  // leaf when count > 0: order_[first, first + count)
    std::uint32_t left = 0, right = 0;
  };

  dvec3 centroid(std::uint32_t i) const {
    const Triangle& t = (*triangles_)[i];
    return t.p0 + (t.e1 + t.e2) / 3.0;
  }

  std::uint32_t build(std::uint32_t begin, std::uint32_t end) {
    const std::uint32_t index = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    Node node;
    node.lo = dvec3(std::numeric_limits<double>::infinity());
    node.hi = -node.lo;
    dvec3 c_lo = node.lo, c_hi = node.hi;
    for (std::uint32_t k = begin; k < end; ++k) {
      const Triangle& t = (*triangles_)[order_[k]];
      for (const dvec3& p : {t.p0, t.p0 + t.e1, t.p0 + t.e2}) {
        node.lo = glm::min(node.lo, p);
        node.hi = glm::max(node.hi, p);
      }
      c_lo = glm::min(c_lo, centroid(order_[k]));
      c_hi = glm::max(c_hi, centroid(order_[k]));
    }
    const dvec3 extent = c_hi - c_lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    if (end - begin <= 4 || extent[axis] <= 0.0) {
      node.first = begin;
      node.count = end - begin;
    } else {
      const std::uint32_t mid = begin + (end - begin) / 2;
      std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                       [&](std::uint32_t a, std::uint32_t b) { return centroid(a)[axis] < centroid(b)[axis]; });
      node.left = build(begin, mid);
      node.right = build(mid, end);
    }
    nodes_[index] = node;
    return index;
  }

  // Slab test, written out per axis so that a zero direction component needs no infinities.
  static bool box_hit(const Node& node, const dvec3& origin, const dvec3& dir, double t_max) {
    double t0 = 0.0, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
      if (dir[a] == 0.0) {
        if (origin[a] < node.lo[a] || origin[a] > node.hi[a]) return false;
        continue;
      }
      double near = (node.lo[a] - origin[a]) / dir[a], far = (node.hi[a] - origin[a]) / dir[a];
      if (near > far) std::swap(near, far);
      t0 = std::max(t0, near);
      t1 = std::min(t1, far);
      if (t0 > t1) return false;
    }
    return true;
  }

  // Visits the triangles of every leaf whose box the ray reaches before t_max (which the visitor
  // may shrink); stops early when the visitor returns true.
  template <typename Visit>
  bool traverse(const dvec3& origin, const dvec3& dir, Visit visit, const double& t_max) const {
    if (nodes_.empty()) return false;
    std::vector<std::uint32_t> stack{0};
    stack.reserve(64);
    while (!stack.empty()) {
      const Node& node = nodes_[stack.back()];
      stack.pop_back();
      if (!box_hit(node, origin, dir, t_max)) continue;
      if (node.count > 0) {
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k)
          if (visit(order_[k])) return true;
      } else {
        stack.push_back(node.left);
        stack.push_back(node.right);
      }
    }
    return false;
  }

  const std::vector<Triangle>* triangles_ = nullptr;  // owned by the Tracer
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;
};

class Random {
 public:
  Random(std::uint64_t seed, std::uint32_t stream) {
    std::seed_seq sequence{std::uint32_t(seed), std::uint32_t(seed >> 32), stream, 0x7265u};
    engine_.seed(sequence);
  }
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }  // [0, 1), 53 random bits

 private:
  std::mt19937_64 engine_;
};

// Uniform direction on the hemisphere around n (pdf 1/(2 pi) per steradian): cos(theta) is uniform.
dvec3 uniform_hemisphere(const dvec3& n, Random& random) {
  const double cos_theta = random.uniform();
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * random.uniform();
  const dvec3 helper = std::abs(n.x) > 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
  const dvec3 t = glm::normalize(glm::cross(helper, n));
  const dvec3 b = glm::cross(n, t);
  return sin_theta * std::cos(phi) * t + sin_theta * std::sin(phi) * b + cos_theta * n;
}

class Tracer {
 public:
  Tracer(const Tracer&) = delete;  // the BVH points into triangles_
  Tracer(const Scene& scene, ReferenceEstimator estimator) : estimator_(estimator) {
    if (scene.materials.empty()) throw std::invalid_argument("render_reference: scene has no materials");
    double scale = 0.0;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
      const SceneTriangle& st = scene.triangles[i];
      if (st.material >= scene.materials.size())
        throw std::invalid_argument("render_reference: triangle " + std::to_string(i) + " has material " +
                                    std::to_string(st.material) + " of " + std::to_string(scene.materials.size()));
      Triangle t;
      t.p0 = dvec3(st.p[0]);
      t.e1 = dvec3(st.p[1]) - t.p0;
      t.e2 = dvec3(st.p[2]) - t.p0;
      const dvec3 c = glm::cross(t.e1, t.e2);
      const double twice_area = glm::length(c);
      if (!(twice_area > 0.0) || !std::isfinite(twice_area)) continue;  // degenerate: invisible
      t.normal = c / twice_area;
      t.area = 0.5 * twice_area;
      t.material = st.material;
      for (const dvec3& p : {t.p0, t.p0 + t.e1, t.p0 + t.e2}) scale = std::max(scale, glm::length(p));
      triangles_.push_back(t);
    }
    t_min_ = 1e-9 * std::max(scale, 1e-3);
    bvh_ = Bvh(triangles_);
    materials_ = scene.materials;
    for (std::uint32_t i = 0; i < triangles_.size(); ++i) {
      if (emission(triangles_[i]) == dvec3(0.0)) continue;
      emitters_.push_back(i);
      emitter_area_ += triangles_[i].area;
      emitter_cdf_.push_back(emitter_area_);
    }
  }

  // One path sample of the radiance arriving at origin from direction -dir.
  dvec3 radiance(dvec3 origin, dvec3 dir, Random& random, std::uint64_t& rays) const {
    dvec3 L(0.0), beta(1.0);
    std::uint32_t from = kNone;
    for (int depth = 0; depth <= kMaxDepth; ++depth) {
      ++rays;
      const Hit hit = bvh_.closest(origin, dir, from, t_min_);
      if (hit.triangle == kNone) break;  // no environment light
      const Triangle& tri = triangles_[hit.triangle];
      const SceneMaterial& material = materials_[tri.material];
      const dvec3 wo = -dir;
      const bool front = glm::dot(tri.normal, wo) > 0.0;
      if (!front && !material.double_sided) break;  // the back of a single-sided surface is black
      const dvec3 n = front ? tri.normal : -tri.normal;
      const dvec3 x = tri.p0 + hit.u * tri.e1 + hit.v * tri.e2;

      if (depth == 0 || estimator_ == ReferenceEstimator::hemisphere) L += beta * dvec3(material.emission);
      if (estimator_ == ReferenceEstimator::hemisphere_nee)
        L += beta * direct_light(x, n, wo, material, hit.triangle, random, rays);

      const dvec3 wi = uniform_hemisphere(n, random);
      beta *= reference_detail::phong_brdf(material, n, wo, wi) * glm::dot(n, wi) * (2.0 * kPi);
      if (beta == dvec3(0.0)) break;
      if (depth + 1 >= kRouletteFromDepth) {
        if (random.uniform() >= kRouletteSurvival) break;
        beta /= kRouletteSurvival;
      }
      origin = x;
      dir = wi;
      from = hit.triangle;
    }
    return L;
  }

 private:
  dvec3 emission(const Triangle& t) const { return dvec3(materials_[t.material].emission); }

  // Emitted radiance reaching x from a point chosen uniformly over all emitter area (pdf 1/A).
  dvec3 direct_light(const dvec3& x, const dvec3& n, const dvec3& wo, const SceneMaterial& material,
                     std::uint32_t at, Random& random, std::uint64_t& rays) const {
    if (emitters_.empty()) return dvec3(0.0);
    const double pick = random.uniform() * emitter_area_;
    std::size_t k = std::upper_bound(emitter_cdf_.begin(), emitter_cdf_.end(), pick) - emitter_cdf_.begin();
    k = std::min(k, emitters_.size() - 1);
    const std::uint32_t index = emitters_[k];
    const Triangle& light = triangles_[index];
    const double su = std::sqrt(random.uniform()), r2 = random.uniform();
    const dvec3 y = light.p0 + (su * (1.0 - r2)) * light.e1 + (su * r2) * light.e2;  // uniform on the triangle

    const dvec3 to_light = y - x;
    const double dist2 = glm::dot(to_light, to_light);
    if (!(dist2 > 0.0)) return dvec3(0.0);
    const double dist = std::sqrt(dist2);
    const dvec3 wi = to_light / dist;
    const double cos_x = glm::dot(n, wi);
    if (cos_x <= 0.0) return dvec3(0.0);
    double cos_y = glm::dot(light.normal, -wi);
    if (cos_y <= 0.0 && !materials_[light.material].double_sided) return dvec3(0.0);  // its back: dark
    cos_y = std::abs(cos_y);
    if (cos_y == 0.0) return dvec3(0.0);
    ++rays;
    if (bvh_.occluded(x, wi, t_min_, dist * (1.0 - 1e-9), at, index)) return dvec3(0.0);
    return reference_detail::phong_brdf(material, n, wo, wi) * emission(light) *
           (cos_x * cos_y / dist2 * emitter_area_);
  }

  ReferenceEstimator estimator_;
  std::vector<Triangle> triangles_;
  std::vector<SceneMaterial> materials_;
  Bvh bvh_;
  double t_min_ = 0.0;
  std::vector<std::uint32_t> emitters_;
  std::vector<double> emitter_cdf_;  // running sum of emitter areas
  double emitter_area_ = 0.0;
};

}  // namespace

ReferenceResult render_reference(const Scene& scene, int width, int height, int spp, std::uint64_t seed,
                                  const ReferenceOptions& options) {
  if (width <= 0 || height <= 0 || spp < 2)
    throw std::invalid_argument("render_reference: need width, height >= 1 and spp >= 2, got " +
                                std::to_string(width) + "x" + std::to_string(height) + " at " +
                                std::to_string(spp) + " spp");
  const auto start = std::chrono::steady_clock::now();
  const Tracer tracer(scene, options.estimator);

  // Pinhole camera: orthonormal (right, up, forward) from the scene camera.
  const SceneCamera& cam = scene.camera;
  const dvec3 forward = glm::normalize(dvec3(cam.forward));
  const dvec3 up = glm::normalize(dvec3(cam.up) - glm::dot(dvec3(cam.up), forward) * forward);
  const dvec3 right = glm::cross(forward, up);
  const double tan_half_y = std::tan(0.5 * double(cam.yfov));
  const double tan_half_x = tan_half_y * double(width) / double(height);
  const dvec3 eye(cam.position);

  ReferenceResult result;
  result.mean = ImageRGB(width, height);
  result.std_error = ImageRGB(width, height);
  result.paths = std::uint64_t(width) * height * spp;

  std::atomic<int> next_row{0};
  std::atomic<std::uint64_t> total_rays{0};
  auto worker = [&] {
    std::uint64_t rays = 0;
    for (int y = next_row++; y < height; y = next_row++) {
      Random random(seed, std::uint32_t(y));  // one stream per row: independent of thread count
      for (int x = 0; x < width; ++x) {
        dvec3 mean(0.0), m2(0.0);  // Welford's running mean and sum of squared deviations
        for (int s = 0; s < spp; ++s) {
          const double px = (x + random.uniform()) / width, py = (y + random.uniform()) / height;
          const dvec3 dir = glm::normalize(forward + (2.0 * px - 1.0) * tan_half_x * right +
                                           (1.0 - 2.0 * py) * tan_half_y * up);
          const dvec3 L = tracer.radiance(eye, dir, random, rays);
          const dvec3 delta = L - mean;
          mean += delta / double(s + 1);
          m2 += delta * (L - mean);
        }
        const dvec3 std_error = glm::sqrt(m2 / double(spp - 1) / double(spp));
        for (int c = 0; c < 3; ++c) {
          result.mean.pixel(x, y)[c] = float(mean[c]);
          result.std_error.pixel(x, y)[c] = float(std_error[c]);
        }
      }
    }
    total_rays += rays;
  };
  int threads = options.threads > 0 ? options.threads : int(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, height);
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();

  result.rays = total_rays;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace bp

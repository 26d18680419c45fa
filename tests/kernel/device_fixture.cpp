#include "kernel/device_fixture.h"

#include <cmath>

#include "device/device_scene.h"
#include "passes/combined.h"
#include "passes/path_tracer.h"
#include "scene/bvh.h"
#include "scene/patches.h"

namespace bp::test {

const DeviceContext& test_device() {
  static DeviceContext device(select_device(""));
  return device;
}

RenderRun render_pt(const Scene& scene, int width, int height, std::uint64_t spp, std::uint32_t seed,
                    std::uint32_t max_depth, bool light_sampling, std::uint32_t light_selection) {
  const DeviceContext& device = test_device();
  PatchLayout patches = build_patch_layout(scene, default_patch_size(scene));
  FlatBvh bvh = build_bvh(scene.triangles);
  DeviceScene device_scene(device, scene, patches, bvh, light_selection);
  PathTracerSettings settings;
  settings.seed = seed;
  settings.max_depth = max_depth;
  settings.light_sampling = light_sampling;
  Accumulator accum(width, height);
  PathTracerPass pass(device, device_scene, pack_camera(scene.camera, width, height), settings, accum);
  std::atomic<bool> never{false};
  RenderRun run;
  run.outcome = run_progressive(pass, RenderBudget{spp, 0.0}, never, nullptr);
  run.image = accum.mean();
  return run;
}

std::unique_ptr<BundleRig> make_bundle_rig(const Scene& scene, float patch_size, std::uint32_t bins,
                                           std::uint32_t seed, int width, int height, std::uint32_t warmup,
                                           std::size_t static_tiled_bytes, float contact_depth_fraction) {
  auto rig = std::make_unique<BundleRig>();
  rig->scene = scene;
  rig->patches = build_patch_layout(rig->scene, patch_size);
  rig->bvh = build_bvh(rig->scene.triangles);
  rig->geometry = build_bundle_geometry(rig->scene, rig->patches);
  rig->device_scene = std::make_unique<DeviceScene>(test_device(), rig->scene, rig->patches, rig->bvh);
  RayBundleSettings settings;
  settings.seed = seed;
  settings.bins = bins;
  settings.warmup = warmup;
  settings.static_tiled_bytes = static_tiled_bytes;
  settings.contact_depth_fraction = contact_depth_fraction;
  rig->accum = Accumulator(width, height);
  rig->pass = std::make_unique<RayBundlePass>(test_device(), *rig->device_scene, rig->geometry,
                                              pack_camera(rig->scene.camera, width, height), settings, rig->accum);
  return rig;
}

RenderRun render_rb(BundleRig& rig, std::uint64_t iterations) {
  std::atomic<bool> never{false};
  RenderRun run;
  run.outcome = run_progressive(*rig.pass, RenderBudget{iterations, 0.0}, never, nullptr);
  run.image = rig.accum.mean();
  return run;
}

Scene make_parallel_squares(float side, float distance, float le) {
  Scene scene;
  SceneMaterial emitter, receiver;
  emitter.kd = glm::vec3(0.0f);
  emitter.emission = glm::vec3(le);
  receiver.kd = glm::vec3(0.0f);
  scene.materials = {emitter, receiver};
  const float s = side, d = distance;
  // Emitter at z = 0 facing +z (counter-clockwise seen from +z).
  scene.triangles.push_back({{{0, 0, 0}, {s, 0, 0}, {s, s, 0}}, 0});
  scene.triangles.push_back({{{0, 0, 0}, {s, s, 0}, {0, s, 0}}, 0});
  // Receiver at z = d facing -z.
  scene.triangles.push_back({{{0, 0, d}, {s, s, d}, {s, 0, d}}, 1});
  scene.triangles.push_back({{{0, 0, d}, {0, s, d}, {s, s, d}}, 1});
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  scene.camera.position = glm::vec3(0.5f * s, 0.5f * s, 0.5f * d);
  scene.camera.forward = glm::vec3(0, 0, 1);
  scene.camera.up = glm::vec3(0, 1, 0);
  return scene;
}

double parallel_rectangles_form_factor(double a, double b, double c) {
  // Hottel's crossed-strings result for directly opposed parallel rectangles (e.g. Howell's catalogue, C-11).
  const double x = a / c, y = b / c;
  const double t1 = std::log(std::sqrt((1 + x * x) * (1 + y * y) / (1 + x * x + y * y)));
  const double t2 = x * std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y));
  const double t3 = y * std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x));
  return 2.0 / (M_PI * x * y) * (t1 + t2 + t3 - x * std::atan(x) - y * std::atan(y));
}

CombinedRun render_combined(const Scene& scene, int width, int height, const CombinedSettings& cs) {
  const DeviceContext& device = test_device();
  PatchLayout patches = build_patch_layout(scene, cs.patch_size, cs.cluster_size);
  FlatBvh bvh = build_bvh(scene.triangles);
  BundleGeometry geometry = build_bundle_geometry(scene, patches);
  DeviceScene device_scene(device, scene, patches, bvh, cs.light_selection);
  const CameraParams camera = pack_camera(scene.camera, width, height);
  const RoundShape shape{cs.pt_samples_per_round, cs.rb_iterations_per_round};
  const CombinedWeights weights = combined_weights(cs.weight_mode, shape);  // pt_samples_per_round 0: RB alone
  Accumulator pt_accum(width, height), rb_accum(width, height);
  PathTracerSettings pts;
  pts.seed = cs.seed;
  pts.weight_mode = weights.mode;
  pts.weight_ratio = weights.ratio_n2_over_n1;
  pts.beta_heuristic = cs.beta_heuristic;
  pts.rb_light_rate = cs.light_rate;
  pts.light_sampling = cs.light_sampling;
  pts.eye_direct_shared = cs.eye_direct_shared;
  pts.rb_sun_own = cs.sun_own;
  PathTracerPass pt(device, device_scene, camera, pts, pt_accum);
  RayBundleSettings rbs;
  rbs.seed = cs.seed;
  rbs.bins = cs.bins;
  rbs.warmup = cs.warmup;
  rbs.weight_mode = weights.mode;
  rbs.weight_ratio = weights.ratio_n2_over_n1;
  rbs.beta_heuristic = cs.beta_heuristic;
  rbs.light_rate = cs.light_rate;
  rbs.light_sampling = cs.light_sampling;
  rbs.eye_direct_shared = cs.eye_direct_shared;
  rbs.sun_own = cs.sun_own;
  RayBundlePass rb(device, device_scene, geometry, camera, rbs, rb_accum);
  CombinedPass combined(pt, rb, shape);
  std::atomic<bool> never{false};
  CombinedRun run;
  run.outcome = run_progressive(combined, RenderBudget{cs.rounds, 0.0}, never, nullptr);
  run.pt = pt_accum.mean();
  run.rb = rb_accum.mean();
  run.pt_max_batch = pt.max_batch();
  run.rb_max_batch = rb.max_batch();
  run.combined = run.pt;
  for (std::size_t i = 0; i < run.combined.rgb.size(); ++i) run.combined.rgb[i] += run.rb.rgb[i];
  return run;
}

Scene subdivide_non_emitters(const Scene& scene, std::uint32_t k) {
  Scene out = scene;
  out.triangles.clear();
  for (const SceneTriangle& t : scene.triangles) {
    if (scene.materials[t.material].emission != glm::vec3(0.0f)) {
      out.triangles.push_back(t);
      continue;
    }
    for (std::uint32_t local = 0; local < k * k; ++local) {
      float b1[3], b2[3];
      patch_corner_barycentrics(local, k, b1, b2);
      SceneTriangle sub = t;
      for (int c = 0; c < 3; ++c) sub.p[c] = t.p[0] + b1[c] * (t.p[1] - t.p[0]) + b2[c] * (t.p[2] - t.p[0]);
      out.triangles.push_back(sub);
    }
  }
  return out;
}

Scene make_glossy_light_box() {
  SceneMaterial walls, floor, light;
  walls.kd = glm::vec3(0.6f, 0.55f, 0.5f);
  floor.kd = glm::vec3(0.3f);
  floor.ks = glm::vec3(0.5f);
  floor.shininess = 30.0f;
  light.kd = glm::vec3(0.0f);
  light.emission = glm::vec3(8.0f);
  Scene scene = make_closed_box(0.5f, walls);
  scene.materials = {walls, floor, light};
  for (SceneTriangle& t : scene.triangles)
    if (t.p[0].y == -0.5f && t.p[1].y == -0.5f && t.p[2].y == -0.5f) t.material = 1;
  const float y = 0.499f, a = -0.15f, b = 0.15f;  // facing down: clockwise seen from below
  scene.triangles.push_back({{{a, y, a}, {b, y, a}, {b, y, b}}, 2});
  scene.triangles.push_back({{{a, y, a}, {b, y, b}, {a, y, b}}, 2});
  scene.camera.position = glm::vec3(0.0f, 0.1f, 0.45f);
  scene.camera.forward = glm::normalize(glm::vec3(0.0f, -0.45f, -1.0f));
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 1.1f;
  return scene;
}

Scene make_multi_light_box() {
  Scene scene = make_glossy_light_box();
  SceneMaterial partition = scene.materials[0], wall_light, hanging;
  partition.double_sided = true;
  wall_light.kd = hanging.kd = glm::vec3(0.0f);
  wall_light.emission = glm::vec3(60.0f, 50.0f, 40.0f);  // bright, behind the partition: power and tree differ most
  hanging.emission = glm::vec3(2.0f, 3.0f, 4.0f);
  hanging.double_sided = true;
  const std::uint32_t m = std::uint32_t(scene.materials.size());
  scene.materials.insert(scene.materials.end(), {partition, wall_light, hanging});
  const float x = 0.2f, top = 0.3f;
  scene.triangles.push_back({{{x, -0.5f, -0.5f}, {x, top, -0.5f}, {x, top, 0.5f}}, m});
  scene.triangles.push_back({{{x, -0.5f, -0.5f}, {x, top, 0.5f}, {x, -0.5f, 0.5f}}, m});
  const float w = 0.499f;  // on the +x wall, facing -x: counter-clockwise seen from -x
  scene.triangles.push_back({{{w, -0.1f, -0.1f}, {w, -0.1f, 0.1f}, {w, 0.1f, 0.1f}}, m + 1});
  scene.triangles.push_back({{{w, -0.1f, -0.1f}, {w, 0.1f, 0.1f}, {w, 0.1f, -0.1f}}, m + 1});
  scene.triangles.push_back({{{-0.3f, 0.1f, -0.2f}, {-0.2f, 0.1f, -0.25f}, {-0.25f, 0.25f, -0.2f}}, m + 2});
  ScenePunctualLight point, spot;
  point.position = glm::vec3(-0.25f, -0.3f, 0.1f);
  point.intensity = glm::vec3(0.05f, 0.06f, 0.08f);
  spot.kind = ScenePunctualLight::Kind::spot;
  spot.position = glm::vec3(-0.1f, 0.35f, -0.3f);
  spot.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f));
  spot.intensity = glm::vec3(0.3f);
  spot.inner_cone = 0.2f;
  spot.outer_cone = 0.6f;
  scene.lights = {point, spot};
  return scene;
}

Scene make_closed_box(float h, const SceneMaterial& material) {
  Scene scene;
  scene.materials.push_back(material);
  const glm::vec3 c[8] = {{-h, -h, -h}, {h, -h, -h}, {h, h, -h}, {-h, h, -h},
                          {-h, -h, h},  {h, -h, h},  {h, h, h},  {-h, h, h}};
  // Each face as a quad whose counter-clockwise order, seen from inside, gives an inward normal.
  const int faces[6][4] = {{0, 1, 2, 3}, {5, 4, 7, 6}, {4, 0, 3, 7}, {1, 5, 6, 2}, {4, 5, 1, 0}, {3, 2, 6, 7}};
  for (const auto& f : faces) {
    scene.triangles.push_back({{c[f[0]], c[f[1]], c[f[2]]}, 0});
    scene.triangles.push_back({{c[f[0]], c[f[2]], c[f[3]]}, 0});
  }
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& p : t.p) scene.bounds.grow(p);
  scene.camera.position = glm::vec3(0.1f * h, -0.05f * h, 0.02f * h);
  scene.camera.forward = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
  scene.camera.up = glm::normalize(glm::cross(glm::cross(scene.camera.forward, glm::vec3(0, 1, 0)), scene.camera.forward));
  scene.camera.yfov = 1.2f;
  return scene;
}

}  // namespace bp::test

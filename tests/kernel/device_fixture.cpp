#include "kernel/device_fixture.h"

#include "device/device_scene.h"
#include "passes/path_tracer.h"
#include "scene/bvh.h"
#include "scene/patches.h"

namespace bp::test {

const DeviceContext& test_device() {
  static DeviceContext device(select_device(""));
  return device;
}

RenderRun render_pt(const Scene& scene, int width, int height, std::uint64_t spp, std::uint32_t seed,
                    std::uint32_t max_depth) {
  const DeviceContext& device = test_device();
  PatchLayout patches = build_patch_layout(scene, default_patch_size(scene));
  FlatBvh bvh = build_bvh(scene.triangles);
  DeviceScene device_scene(device, bvh, pack_triangle_shading(scene, patches), pack_materials(scene));
  PathTracerSettings settings;
  settings.seed = seed;
  settings.max_depth = max_depth;
  PathTracerPass pass(device, device_scene, pack_camera(scene.camera, width, height), ray_epsilon_for(scene.bounds),
                      settings);
  Accumulator accum(width, height);
  std::atomic<bool> never{false};
  RenderRun run;
  run.outcome = run_path_tracer(pass, accum, RenderBudget{spp, 0.0}, never, nullptr);
  run.image = accum.mean();
  return run;
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

// alphaMode MASK on the host (kernels/shared/alpha_mask.h): rays, shadow rays among them, pass where
// the texture's alpha is below the cutoff and stop elsewhere; RB's elements know which part of them
// is there.
#include "kernels/shared/alpha_mask.h"
#include "device/device_scene.h"
#include "scene/bvh.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"
#include "scene/patches.h"
#include "scene/textures.h"

#include <gtest/gtest.h>

namespace bp {
namespace {

// good/alpha-mask-quad.gltf (the unit quad in z = 0, its top-right texel x, y in [3/4, 1] cut away)
// with an opaque quad 1 m behind it.
Scene masked_quad_before_a_wall() {
  Scene scene = load_gltf(test::test_file("good/alpha-mask-quad.gltf"));
  const glm::vec3 p[4] = {{-1, -1, -1}, {2, -1, -1}, {2, 2, -1}, {-1, 2, -1}};
  scene.triangles.push_back({{p[0], p[1], p[2]}, 0});
  scene.triangles.push_back({{p[0], p[2], p[3]}, 0});
  for (const SceneTriangle& t : scene.triangles)
    for (const glm::vec3& q : t.p) scene.bounds.grow(q);
  return scene;
}

TEST(AlphaMask, RaysAndShadowRaysPassWhereAlphaIsBelowTheCutoff) {
  const Scene scene = masked_quad_before_a_wall();
  ASSERT_TRUE(scene.has_alpha_masks());
  const FlatBvh bvh = build_bvh(scene.triangles);
  const PatchLayout patches = build_patch_layout(scene, default_patch_size(scene));
  const std::vector<TriangleShading> shading = pack_triangle_shading(scene, patches);
  const std::vector<MaterialTextures> materials = pack_material_textures(scene);
  const std::vector<float> texcoords = pack_texcoords(scene);
  const TextureSet set = host_texture_set(scene, materials, texcoords);
  for (float y = 0.05f; y < 1.0f; y += 0.1f)
    for (float x = 0.05f; x < 1.0f; x += 0.1f) {
      const bool cut = x > 0.75f && y > 0.75f;
      const float3 origin = make_float3(x, y, 1.0f), dir = make_float3(0.0f, 0.0f, -1.0f);
      Hit hit;
      ASSERT_TRUE(closest_surface_hit(bvh.nodes.data(), bvh.triangles.data(), shading.data(), &set, 1u, origin, dir,
                                      BP_FLOAT_MAX, 1e-5f, &hit));
      EXPECT_NEAR(hit.t, cut ? 2.0f : 1.0f, 1e-4f) << x << "," << y;
      EXPECT_EQ(surface_occludes(bvh.nodes.data(), bvh.triangles.data(), shading.data(), &set, 1u, origin, dir, 1.5f,
                                 1e-5f),
                cut ? 0 : 1)
          << x << "," << y;
      // without masks (masks 0) every ray stops at the quad
      ASSERT_TRUE(closest_surface_hit(bvh.nodes.data(), bvh.triangles.data(), shading.data(), &set, 0u, origin, dir,
                                      BP_FLOAT_MAX, 1e-5f, &hit));
      EXPECT_NEAR(hit.t, 1.0f, 1e-4f);
    }
  // RB's elements: the surface fraction of the quad's area is 15/16, its patches' coverage between 0 and 1
  const std::vector<float> coverage = element_alpha_coverage(scene, patches);
  double surface = 0.0, area = 0.0;
  std::size_t e = 0;
  for_each_sub_triangle(scene, patches, [&](const SubTriangle& sub) {
    const double a = 0.5 * sub.parent_area2 / sub.k2;
    if (sub.triangle < 2) {
      surface += coverage[e] * a;
      area += a;
    } else {
      EXPECT_EQ(coverage[e], 1.0f);  // not masked
    }
    EXPECT_TRUE(coverage[e] >= 0.0f && coverage[e] <= 1.0f);
    ++e;
  });
  EXPECT_NEAR(surface / area, 15.0 / 16.0, 0.01);
}

}  // namespace
}  // namespace bp

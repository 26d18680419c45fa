// Hand-made files of tests/data/gltf (written by make_test_files.py there): what the loader
// accepts, how it maps materials, and the one-line errors for every kind of broken file.
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>

#include <map>

namespace bp {
namespace {

using test::has_warning;
using test::test_file;

void expect_vec3_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

TEST(GltfLoader, ExternalBinBesideTheFile) {
  const Scene s = load_gltf(test_file("good/external-bin.gltf"));
  EXPECT_EQ(s.triangles.size(), 1u);
}

TEST(GltfLoader, BinaryGlb) {
  const Scene s = load_gltf(test_file("good/triangle.glb"));
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_vec3_near(s.triangles[0].p[1], {1, 0, 0});
  EXPECT_EQ(s.triangles[0].material, 1u);
}

TEST(GltfLoader, StridedBufferView) {
  const Scene s = load_gltf(test_file("good/strided.gltf"));
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_vec3_near(s.triangles[0].p[2], {0, 1, 0});
}

TEST(GltfLoader, SparseAccessorWithoutBufferView) {
  const Scene s = load_gltf(test_file("good/sparse-no-view.gltf"));
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_vec3_near(s.triangles[0].p[0], {0, 0, 1});
  expect_vec3_near(s.triangles[0].p[1], {2, 0, 1});
  expect_vec3_near(s.triangles[0].p[2], {0, 3, 1});
}

TEST(GltfLoader, MaterialMapping) {
  const Scene s = load_gltf(test_file("good/materials.gltf"));
  ASSERT_EQ(s.materials.size(), 10u);
  ASSERT_EQ(s.triangles.size(), 10u);
  // Index 0 is the default material; file material i is at i + 1.
  expect_vec3_near(s.materials[0].kd, glm::vec3(0.8f));
  expect_vec3_near(s.materials[0].ks, glm::vec3(0.0f));
  EXPECT_FALSE(s.materials[0].ggx);
  for (std::uint32_t i = 0; i < 9; ++i) EXPECT_EQ(s.triangles[i].material, i + 1);
  EXPECT_EQ(s.triangles[9].material, 0u);

  const SceneMaterial& phong = s.materials[1];  // extras.phong wins over the PBR fields
  EXPECT_FALSE(phong.ggx);
  expect_vec3_near(phong.kd, {0.2f, 0.3f, 0.4f});
  expect_vec3_near(phong.ks, glm::vec3(0.5f));
  EXPECT_FLOAT_EQ(phong.shininess, 20.0f);

  // Core glTF is the metallic-roughness BRDF (docs/design.md §11): its factors as they are, no Phong mapping.
  const SceneMaterial& core_default = s.materials[2];  // baseColor 1, metallic 1, roughness 1
  EXPECT_TRUE(core_default.ggx);
  expect_vec3_near(core_default.base_color, glm::vec3(1.0f));
  EXPECT_FLOAT_EQ(core_default.metallic, 1.0f);
  EXPECT_FLOAT_EQ(core_default.roughness, 1.0f);
  expect_vec3_near(core_default.dielectric_f0, glm::vec3(0.04f));  // ior 1.5: ((1.5 - 1) / (1.5 + 1))^2
  EXPECT_FLOAT_EQ(core_default.specular_weight, 1.0f);

  const SceneMaterial& pbr = s.materials[3];  // base (0.5, 0.25, 0.9), metallic 0.5, rough 0.5, specular 0.5
  EXPECT_TRUE(pbr.ggx);
  expect_vec3_near(pbr.base_color, {0.5f, 0.25f, 0.9f});
  EXPECT_FLOAT_EQ(pbr.metallic, 0.5f);
  EXPECT_FLOAT_EQ(pbr.roughness, 0.5f);
  EXPECT_FLOAT_EQ(pbr.specular_weight, 0.5f);  // KHR_materials_specular scales f0 and f90, not f0 itself
  expect_vec3_near(pbr.dielectric_f0, glm::vec3(0.04f));

  const SceneMaterial& bright = s.materials[4];  // Phong's kd + ks = 1.6 in red: scaled by 1/1.6
  expect_vec3_near(bright.kd, {0.5f, 0.125f, 0.125f});
  expect_vec3_near(bright.ks, {0.5f, 0.125f, 0.125f});
  EXPECT_TRUE(has_warning(s, "\"too bright\""));

  const SceneMaterial& lamp = s.materials[5];
  expect_vec3_near(lamp.emission, {4.0f, 2.0f, 1.0f});  // emissiveFactor x emissiveStrength 4
  EXPECT_TRUE(lamp.double_sided);
  EXPECT_TRUE(lamp.ggx);
  EXPECT_FLOAT_EQ(lamp.roughness, 0.0f);  // the sharpest lobe (BP_GGX_MIN_ALPHA)
  EXPECT_FALSE(phong.double_sided);

  // KHR_materials_specular.specularColorFactor [0, 0, 0] (Blender's Specular 0): f0 = 0, but the
  // specification keeps f90 = specular = 1, so grazing light still reflects (Schlick's (1 - v.h)^5).
  const SceneMaterial& blender = s.materials[6];
  EXPECT_TRUE(blender.ggx);
  expect_vec3_near(blender.dielectric_f0, glm::vec3(0.0f));
  EXPECT_FLOAT_EQ(blender.specular_weight, 1.0f);
  EXPECT_FALSE(has_warning(s, "\"blender specular 0\""));
  // dielectric_f0 = min(f0(ior) specularColor, 1), specular apart
  const SceneMaterial& coloured = s.materials[7];  // base 0.5, metallic 0.5, specular 0.5, colour (1, 0.5, 0)
  expect_vec3_near(coloured.dielectric_f0, 0.04f * glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_FLOAT_EQ(coloured.specular_weight, 0.5f);
  const SceneMaterial& water = s.materials[8];  // KHR_materials_ior 1.33, specular colour (100, 1, 0.5)
  const float f0_water = (0.33f / 2.33f) * (0.33f / 2.33f);
  expect_vec3_near(water.dielectric_f0, {1.0f, f0_water, 0.5f * f0_water}, 1e-6f);
  EXPECT_FLOAT_EQ(water.roughness, 0.1f);
  // specular 0, metallic 0: exactly Lambert, kd = baseColor (and gathered in blocks by RB)
  const SceneMaterial& no_specular = s.materials[9];
  EXPECT_FALSE(no_specular.ggx);
  expect_vec3_near(no_specular.kd, glm::vec3(0.6f));
  expect_vec3_near(no_specular.ks, glm::vec3(0.0f));
  // glTF's model conserves energy by construction: no kd + ks warning for any of them
  for (const char* name : {"\"pbr default\"", "\"pbr\"", "\"lamp\"", "\"coloured specular\"", "\"water\""})
    EXPECT_FALSE(has_warning(s, name)) << name;

  EXPECT_EQ(s.emissive_triangles(), 1u);
  EXPECT_FALSE(has_warning(s, "no emitter"));
}

TEST(GltfLoader, HierarchyTransformsAndMirroredWinding) {
  const Scene s = load_gltf(test_file("good/hierarchy.gltf"));
  ASSERT_EQ(s.triangles.size(), 4u);  // the quad, instanced twice
  // Child 1: scale 2 under translation 10; child 2: mirrored in x, at -5, under translation 10.
  expect_vec3_near(s.bounds.lo, {4, 0, 0});
  expect_vec3_near(s.bounds.hi, {12, 2, 0});
  for (const auto& t : s.triangles) EXPECT_GT(test::normal_of(t).z, 0.0f) << "front face must stay +z";
  // Camera: rotated a quarter turn about +y, so it looks down -x.
  EXPECT_TRUE(s.camera.from_file);
  expect_vec3_near(s.camera.position, {0, 0, 5});
  expect_vec3_near(s.camera.forward, {-1, 0, 0});
  expect_vec3_near(s.camera.up, {0, 1, 0});
  EXPECT_FLOAT_EQ(s.camera.yfov, 0.5f);
  EXPECT_EQ(s.camera.aspect, 0.0f);  // not given
}

// NORMAL: read per corner, carried through the node transform by its inverse transpose, a zero one
// replaced by the flat normal with a warning; a file without NORMAL has no shading normals.
TEST(GltfLoader, NormalsAreReadAndTransformed) {
  const Scene s = load_gltf(test_file("good/normals.gltf"));
  ASSERT_EQ(s.triangles.size(), 1u);
  const SceneTriangle& t = s.triangles[0];
  ASSERT_TRUE(t.has_normals);
  EXPECT_TRUE(s.has_shading_normals());
  expect_vec3_near(t.normal[0], {0, 0, 1});
  expect_vec3_near(t.normal[1], glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f)));  // scale (2, 1, 1): x / 2
  expect_vec3_near(t.normal[2], {0, 0, 1});  // zero in the file: the flat normal
  EXPECT_TRUE(has_warning(s, "1 triangle corner(s) have a zero NORMAL"));
  EXPECT_FALSE(load_gltf(test_file("good/strided.gltf")).has_shading_normals());
}

TEST(GltfLoader, NoScenesDrawsEveryRootNode) {
  const Scene s = load_gltf(test_file("good/no-scenes.gltf"));
  EXPECT_EQ(s.triangles.size(), 2u);
  EXPECT_FLOAT_EQ(s.bounds.lo.z, 1.0f);
  EXPECT_FLOAT_EQ(s.bounds.hi.z, 2.0f);
}

TEST(GltfLoader, OrthographicOnlyFallsBackToDefaultView) {
  const Scene s = load_gltf(test_file("good/ortho-camera.gltf"));
  EXPECT_FALSE(s.camera.from_file);
  EXPECT_TRUE(has_warning(s, "orthographic"));
  EXPECT_TRUE(has_warning(s, "no camera in file; using a default view"));
}

TEST(GltfLoader, DegenerateTrianglesDroppedWithOneWarning) {
  const Scene s = load_gltf(test_file("good/degenerate.gltf"));
  EXPECT_EQ(s.triangles.size(), 1u);
  EXPECT_TRUE(has_warning(s, "dropped 1 degenerate"));
}

// KHR_lights_punctual: candela become W/sr and lux W/m^2 at 683 lm/W; the node places and turns the light.
TEST(GltfLoader, PunctualLights) {
  const Scene s = load_gltf(test_file("good/lights.gltf"));
  ASSERT_EQ(s.lights.size(), 3u);
  const ScenePunctualLight& spot = s.lights[0];
  EXPECT_EQ(spot.kind, ScenePunctualLight::Kind::spot);
  expect_vec3_near(spot.position, {0, 2, 0});
  expect_vec3_near(spot.direction, {0, -1, 0});
  expect_vec3_near(spot.intensity, {1.0f, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(spot.inner_cone, 0.25f);
  EXPECT_FLOAT_EQ(spot.outer_cone, 0.5f);
  EXPECT_EQ(s.lights[1].kind, ScenePunctualLight::Kind::point);
  expect_vec3_near(s.lights[1].intensity, glm::vec3(2.0f));
  const ScenePunctualLight& sun = s.lights[2];
  EXPECT_EQ(sun.kind, ScenePunctualLight::Kind::directional);
  expect_vec3_near(sun.intensity, glm::vec3(3.0f));  // 2049 lux / 683 lm/W
  expect_vec3_near(sun.direction, {0, 0, -1});       // the node's -z
  EXPECT_FALSE(has_warning(s, "directional"));  // taken, not skipped
  EXPECT_FALSE(has_warning(s, "no emitter"));  // punctual lights light the scene
}

// Exported by Blender's glTF exporter (scripts/make_blender_point_light_scene.py): one point light,
// 100 W in Blender, and nothing the loader has to warn about.
TEST(GltfLoader, BlenderExportWithAPointLight) {
  const Scene s = load_gltf(test::scene_file("blender-point-light.gltf"));
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].kind, ScenePunctualLight::Kind::point);
  EXPECT_NEAR(s.lights[0].intensity.x, 100.0 / (4.0 * M_PI), 0.01);  // W/sr of 100 W in every direction
  expect_vec3_near(s.lights[0].position, {0.0f, 1.9f, 0.0f}, 1e-4f);
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

// The room that bench/blender_compare.sh renders against Cycles (scenes/blender/make_room.py,
// exported by Blender 3.4's glTF exporter as scenes/blender-room.glb): a 20 W/m^2 sun (13660 lux)
// and a 100 W point light in physical units, a floor with an sRGB NEAREST base-colour texture,
// smooth-shaded meshes, Principled BSDFs with Specular 0 -- all read without a warning, as Blender's
// importer reads them back (sun lux / 683, point cd * 4 pi / 683 W).
TEST(GltfLoader, BlenderExportedRoomWithSunPointLightTextureAndSmoothNormals) {
  const Scene s = load_gltf(test::scene_file("blender-room.glb"));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  ASSERT_EQ(s.lights.size(), 2u);
  const ScenePunctualLight* sun = nullptr;
  const ScenePunctualLight* point = nullptr;
  for (const ScenePunctualLight& l : s.lights)
    (l.kind == ScenePunctualLight::Kind::directional ? sun : point) = &l;
  ASSERT_NE(sun, nullptr);
  ASSERT_NE(point, nullptr);
  EXPECT_EQ(point->kind, ScenePunctualLight::Kind::point);
  expect_vec3_near(sun->intensity, glm::vec3(20.0f), 1e-3f);  // Blender's W/m^2: 13660 lux / 683
  // Blender's (1, 0.35, -0.75) of travel, z up, is glTF's (1, -0.75, -0.35), y up
  expect_vec3_near(sun->direction, glm::normalize(glm::vec3(1.0f, -0.75f, -0.35f)), 1e-4f);
  EXPECT_NEAR(point->intensity.x, 100.0 / (4.0 * M_PI), 1e-3);  // 100 W in every direction, W/sr
  expect_vec3_near(point->position, {0.9f, 2.3f, 0.6f}, 1e-4f);  // Blender (0.9, -0.6, 2.3)
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_TRUE(s.has_shading_normals());
  int textured = 0;
  for (const SceneMaterial& m : s.materials) {
    // Specular 0 is specularColorFactor [0, 0, 0]: glTF's model with f0 0 (grazing Fresnel only)
    if (&m != &s.materials[0]) {  // the loader's default material is no file's
      EXPECT_TRUE(m.ggx) << m.name;
      EXPECT_EQ(m.dielectric_f0, glm::vec3(0.0f)) << m.name;
    }
    if (!m.textured()) continue;
    ++textured;
    EXPECT_EQ(m.name, "floor_tiles");
    ASSERT_NE(m.textures.base_color, BP_NO_TEXTURE);
    const TextureView& view = s.texture_views.at(m.textures.base_color);
    EXPECT_EQ(view.width, 64u);
    EXPECT_NE(view.flags & BP_TEXTURE_SRGB, 0u);
    EXPECT_NE(view.flags & BP_TEXTURE_NEAREST, 0u);  // Blender's Closest interpolation
  }
  EXPECT_EQ(textured, 1);
}

// The "real materials" room (scenes/blender/make_pbr_room.py, Blender 5.0's glTF exporter, compared
// with Cycles by bench/pbr_room.sh): Principled BSDFs read as glTF's metallic-roughness model, a
// thin glass pane (KHR_materials_transmission; the default ior, which Blender leaves out), a
// base-colour texture on the floor, a normal map with exported TANGENTs on the back wall, the sun
// and a point light -- all without a warning.
TEST(GltfLoader, BlenderPbrRoomMaterialsGlassTexturesAndLights) {
  const Scene s = load_gltf(test::scene_file("blender-pbr-room.glb"));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_TRUE(s.has_transmission());
  EXPECT_TRUE(s.has_normal_maps());
  std::map<std::string, const SceneMaterial*> by_name;
  for (const SceneMaterial& m : s.materials) by_name[m.name] = &m;
  struct Expected {
    const char* name;
    float metallic, roughness;
  };
  for (const Expected& e : {Expected{"gold", 1.0f, 0.2f}, Expected{"copper", 1.0f, 0.5f},
                            Expected{"red_plastic", 0.0f, 0.4f}, Expected{"glazed_ceramic", 0.0f, 0.05f},
                            Expected{"wood_floor", 0.0f, 0.35f}, Expected{"plaster", 0.0f, 0.9f},
                            Expected{"white_paint", 0.0f, 0.6f}, Expected{"ceiling_paint", 0.0f, 0.6f},
                            Expected{"window_glass", 0.0f, 0.0f}}) {
    ASSERT_TRUE(by_name.count(e.name)) << e.name;
    const SceneMaterial& m = *by_name[e.name];
    EXPECT_TRUE(m.ggx) << e.name;
    EXPECT_NEAR(m.metallic, e.metallic, 1e-6f) << e.name;
    EXPECT_NEAR(m.roughness, e.roughness, 1e-6f) << e.name;
    expect_vec3_near(m.dielectric_f0, glm::vec3(0.04f), 1e-6f);
    EXPECT_EQ(m.has_normal_map(), m.name == "plaster") << e.name;
    EXPECT_EQ(m.textures.base_color != BP_NO_TEXTURE, m.name == "wood_floor") << e.name;
    EXPECT_FLOAT_EQ(m.transmission, m.name == "window_glass" ? 1.0f : 0.0f) << e.name;
  }
  expect_vec3_near(by_name["gold"]->base_color, {1.0f, 0.766f, 0.336f}, 1e-6f);
  EXPECT_FLOAT_EQ(by_name["window_glass"]->ior, 1.5f);
  expect_vec3_near(by_name["window_glass"]->transmission_tint, glm::vec3(1.0f), 1e-6f);
}

// ------------------------------------------------------------------ broken files

struct BadCase {
  const char* file;
  const char* object;  // what the message must name besides the file
};

class GltfBadFile : public ::testing::TestWithParam<BadCase> {};

TEST_P(GltfBadFile, ThrowsOneLineSceneErrorNamingFileAndObject) {
  const BadCase& c = GetParam();
  const std::string path = test_file(std::string("bad/") + c.file);
  try {
    load_gltf(path);
    FAIL() << "loaded " << c.file;
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(c.object), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

INSTANTIATE_TEST_SUITE_P(
    All, GltfBadFile,
    ::testing::Values(
        BadCase{"does-not-exist.gltf", "cannot open"},
        BadCase{"not-gltf.gltf", "not glTF"},
        BadCase{"syntax-error.gltf", "JSON"},
        BadCase{"overflow-number.gltf", "JSON"},
        BadCase{"glb-version.glb", ".glb header"},
        BadCase{"glb-truncated.glb", ".glb header"},
        BadCase{"accessor-index.gltf", "accessor 5 (POSITION of mesh 0 primitive 0) does not exist"},
        BadCase{"indices-accessor-index.gltf", "accessor 7 (indices of mesh 0 primitive 0)"},
        BadCase{"buffer-view-index.gltf", "refers to buffer view 4"},
        BadCase{"buffer-index.gltf", "buffer view 0 refers to buffer 3"},
        BadCase{"accessor-past-view.gltf", "accessor 0 (POSITION of mesh 0 primitive 0) runs past the end of buffer view 0"},
        BadCase{"view-past-buffer.gltf", "buffer view 1 runs past the end of buffer 0"},
        BadCase{"small-stride.gltf", "buffer view 0 has byteStride 8"},
        BadCase{"index-value.gltf", "accessor 1 (indices of mesh 0 primitive 0) holds index 3"},
        BadCase{"material-index.gltf", "mesh 0 primitive 0 refers to material 2"},
        BadCase{"mesh-index.gltf", "node 0 refers to mesh 1"},
        BadCase{"camera-index.gltf", "node 0 refers to camera 0"},
        BadCase{"child-index.gltf", "node 0 refers to node 9"},
        BadCase{"scene-node-index.gltf", "scene 0 refers to node 4"},
        BadCase{"default-scene.gltf", "scene 2"},
        BadCase{"node-cycle.gltf", "cycle"},
        BadCase{"nan-position.gltf", "non-finite position"},
        BadCase{"infinite-transform.gltf", "node 1 has a non-finite"},
        BadCase{"normalized-positions.gltf", "accessor 0 (POSITION of mesh 0 primitive 0) has unsupported component type"},
        BadCase{"mode.gltf", "mesh 0 primitive 0 has unknown mode 9"},
        BadCase{"points-only.gltf", "no triangles"},
        BadCase{"sparse-index-range.gltf", "sparse index 3 is out of range"},
        BadCase{"sparse-not-increasing.gltf", "sparse indices are not strictly increasing"},
        BadCase{"light-index.gltf", "refers to KHR_lights_punctual light 3"},
        BadCase{"light-cone.gltf", "KHR_lights_punctual light 0 has cone angles"},
        BadCase{"light-intensity.gltf", "KHR_lights_punctual light 0 has intensity"},
        BadCase{"light-type.gltf", "KHR_lights_punctual light 0 has unknown type"},
        BadCase{"normal-type.gltf", "accessor 2 (NORMAL of mesh 0 primitive 0) has type VEC2"},
        BadCase{"normal-count.gltf", "accessor 2 (NORMAL of mesh 0 primitive 0) has 2 elements, but POSITION has 3"},
        BadCase{"normal-component.gltf", "accessor 2 (NORMAL of mesh 0 primitive 0) has unsupported component type"},
        BadCase{"normal-nan.gltf", "accessor 2 (NORMAL of mesh 0 primitive 0) holds a non-finite normal"},
        BadCase{"specular-colour.gltf", "material 0 \"grey\" KHR_materials_specular.specularColorFactor"},
        BadCase{"ior-below-one.gltf", "material 0 \"grey\" KHR_materials_ior.ior is 0.5; it must be 0 or at least 1"},
        BadCase{"metallic-negative.gltf", "material 0 \"grey\" metallicFactor is -0.25; glTF allows [0, 1]"},
        BadCase{"specular-factor-range.gltf", "material 0 \"grey\" KHR_materials_specular.specularFactor is 1.5"},
        BadCase{"base-colour-negative.gltf", "material 0 \"grey\" baseColorFactor is -0.1"},
        BadCase{"uri-parent.gltf", "buffer 0 uri"},
        BadCase{"uri-absolute.gltf", "buffer 0 uri"},
        BadCase{"uri-encoded-parent.gltf", "buffer 0 uri"},
        BadCase{"missing-bin.gltf", "buffer 0 uri \"missing.bin\""},
        BadCase{"texture-missing-image.gltf", "image 0 (\"missing.png\") uri \"missing.png\" names no readable file"},
        BadCase{"texture-undecodable.gltf", "image 0 is not a decodable PNG or JPEG"},
        BadCase{"texture-too-large.gltf", "image 0 is 20000 x 4 texels, beyond the limit of 16384 per side"},
        BadCase{"texcoord-unnormalized.gltf", "accessor 2 (TEXCOORD_0 of mesh 0 primitive 0) has integer components that "
                                              "are not normalized"},
        BadCase{"texcoord-type.gltf", "accessor 2 (TEXCOORD_0 of mesh 0 primitive 0) has type VEC3"},
        BadCase{"texture-index.gltf", "material 0 \"textured\" baseColorTexture refers to texture 5"},
        BadCase{"texture-image-index.gltf", "baseColorTexture (texture 0) refers to image 3"}),
    [](const auto& info) { return bp::test::test_name_from_file(info.param.file); });

}  // namespace
}  // namespace bp

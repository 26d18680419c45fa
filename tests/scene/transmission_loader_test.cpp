// KHR_materials_transmission with KHR_materials_ior and KHR_materials_volume (gltf_loader.cpp,
// read_transmission): a thin-walled pane with the opaque rest scaled, a volume (thickness > 0) as a
// refractor with its attenuation, every part the pane cannot honour named, and bad values refused
// naming the material.
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace bp {
namespace {

using nlohmann::json;
using test::has_warning;

// good/materials.gltf (a primitive for each of its materials) with `materials` in the place of its own.
Scene load_with_materials(const json& materials) {
  std::ifstream in(test::test_file("good/materials.gltf"));
  std::stringstream text;
  text << in.rdbuf();
  json doc = json::parse(text.str());
  json all = materials;
  while (all.size() < doc["materials"].size()) all.push_back(json{{"name", "filler"}});
  doc["materials"] = all;
  doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                           "KHR_materials_specular"};
  return load_gltf_from_memory(doc.dump(), "transmission.gltf", false);
}

json glass(double transmission, json extra_extensions = json::object()) {
  json m = {{"name", "glass"},
            {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.8, 0.5, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}}};
  m["extensions"] = extra_extensions;
  m["extensions"]["KHR_materials_transmission"] = {{"transmissionFactor", transmission}};
  return m;
}

TEST(GltfTransmission, AThinPaneWithItsIorAndTheOpaqueRestScaled) {
  const Scene plain = load_with_materials(json::array({json{{"name", "glass"},
      {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.8, 0.5, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}}}}));
  const Scene s = load_with_materials(json::array({glass(0.75, {{"KHR_materials_ior", {{"ior", 1.33}}}}), glass(1.0)}));
  EXPECT_TRUE(s.has_transmission());
  EXPECT_FALSE(plain.has_transmission());
  const SceneMaterial& m = s.materials[1];
  EXPECT_FLOAT_EQ(m.transmission, 0.75f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.transmission_tint.y, 0.8f);
  // A GGX material's rest is scaled in the kernels (test_thin_glass.cpp): its factors stay.
  ASSERT_TRUE(m.ggx);
  EXPECT_EQ(m.base_color, plain.materials[1].base_color);
  EXPECT_FLOAT_EQ(s.materials[2].ior, 1.5f);  // KHR_materials_ior's default
  // A Lambert one (specular 0, metallic 0) has its kd scaled here: the rest is 1 - transmission.
  json lambert = glass(0.75, {{"KHR_materials_specular", {{"specularFactor", 0.0}}}});
  const Scene l = load_with_materials(json::array({lambert}));
  ASSERT_FALSE(l.materials[1].ggx);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(l.materials[1].kd[c], 0.25f * l.materials[1].transmission_tint[c], 1e-6f);
  EXPECT_FALSE(has_warning(s, "\"glass\""));  // smooth, thin, untextured: nothing dropped
}

TEST(GltfTransmission, AVolumeRefractsWithItsAttenuationAndThicknessZeroIsThin) {
  const Scene s = load_with_materials(json::array(
      {glass(1.0, {{"KHR_materials_volume",
                    {{"thicknessFactor", 0.02}, {"attenuationDistance", 0.5}, {"attenuationColor", {0.5, 1.0, 0.0}}}}}),
       [] { json g = glass(1.0, {{"KHR_materials_volume", {{"thicknessFactor", 0.0}}}}); g["name"] = "thin by zero"; return g; }(),
       [] { json g = glass(1.0, {{"KHR_materials_volume", {{"thicknessFactor", 1.0}}}}); g["name"] = "clear"; return g; }()}));
  const SceneMaterial& volume = s.materials[1];
  EXPECT_TRUE(volume.volume);
  EXPECT_FLOAT_EQ(volume.transmission, 1.0f);
  // -ln(colour) / distance: half the red left after 0.5 m, all the green, none of the blue
  EXPECT_NEAR(volume.attenuation.x, std::log(2.0) / 0.5, 1e-5);
  EXPECT_EQ(volume.attenuation.y, 0.0f);
  EXPECT_GT(volume.attenuation.z, 1e20f);
  EXPECT_FALSE(has_warning(s, "KHR_materials_volume")) << s.warnings.front();
  EXPECT_FALSE(s.materials[2].volume);  // thickness 0: thin-walled, as the specification says
  EXPECT_FLOAT_EQ(s.materials[2].transmission, 1.0f);
  EXPECT_TRUE(s.materials[3].volume);  // no attenuationDistance: a clear medium
  EXPECT_EQ(s.materials[3].attenuation, glm::vec3(0.0f));
}

TEST(GltfTransmission, WhatThePaneCannotHonourIsNamed) {
  json textured = glass(1.0);
  textured["extensions"]["KHR_materials_transmission"]["transmissionTexture"] = {{"index", 0}};
  json rough = glass(1.0);
  rough["name"] = "frosted";
  rough["pbrMetallicRoughness"]["roughnessFactor"] = 0.4;
  json lamp = glass(1.0);
  lamp["name"] = "lamp";
  lamp["emissiveFactor"] = {1.0, 1.0, 1.0};
  json metal = glass(1.0);
  metal["name"] = "metal";
  metal["pbrMetallicRoughness"]["metallicFactor"] = 1.0;
  const Scene s = load_with_materials(json::array({textured, rough, lamp, metal}));
  EXPECT_TRUE(has_warning(s, "\"glass\": KHR_materials_transmission.transmissionTexture ignored"));
  EXPECT_TRUE(has_warning(s, "\"frosted\": roughness"));
  EXPECT_FLOAT_EQ(s.materials[2].transmission, 1.0f);  // rough: still a (smooth) pane
  EXPECT_TRUE(has_warning(s, "\"lamp\" emits: KHR_materials_transmission ignored"));
  EXPECT_EQ(s.materials[3].transmission, 0.0f);
  EXPECT_EQ(s.materials[4].transmission, 0.0f);  // metal does not transmit (glTF), and that is no drop
  EXPECT_FALSE(has_warning(s, "\"metal\""));
}

TEST(GltfTransmission, BadValuesFailNamingTheMaterial) {
  const std::pair<json, std::string> cases[] = {
      {glass(1.5), "material 0 \"glass\" KHR_materials_transmission.transmissionFactor"},
      {glass(-0.1), "material 0 \"glass\" KHR_materials_transmission.transmissionFactor"},
      {glass(1.0, {{"KHR_materials_ior", {{"ior", 0.5}}}}), "material 0 \"glass\" KHR_materials_ior.ior"},
      {glass(1.0, {{"KHR_materials_ior", {{"ior", "high"}}}}), "material 0 \"glass\" KHR_materials_ior.ior is not a number"},
      {glass(1.0, {{"KHR_materials_volume", {{"thicknessFactor", -1.0}}}}), "KHR_materials_volume.thicknessFactor"},
      {glass(1.0, {{"KHR_materials_volume", {{"thicknessFactor", 1.0}, {"attenuationDistance", 0.0}}}}),
       "material 0 \"glass\" KHR_materials_volume.attenuationDistance"},
      {glass(1.0, {{"KHR_materials_volume", {{"thicknessFactor", 1.0}, {"attenuationColor", {1.0, 2.0, 0.5}}}}}),
       "material 0 \"glass\" KHR_materials_volume.attenuationColor"},
  };
  for (const auto& [material, message] : cases) {
    try {
      load_with_materials(json::array({material}));
      ADD_FAILURE() << "loaded " << material.dump();
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  // ior 0 is KHR_materials_ior's "all reflected", not an error
  EXPECT_EQ(load_with_materials(json::array({glass(1.0, {{"KHR_materials_ior", {{"ior", 0.0}}}})})).materials[1].ior, 0.0f);
}

// scenes/glass-window.gltf (scripts/make_glass_window_scene.py): a room lit only by a sun through a
// glazed window; the pane is read as a clear thin pane and nothing is dropped.
TEST(GltfTransmission, TheShippedGlassWindowSceneLoadsWithoutAWarning) {
  const Scene s = load_gltf(test::scene_file("glass-window.gltf"));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  ASSERT_TRUE(s.has_transmission());
  int panes = 0;
  for (const SceneMaterial& m : s.materials) {
    if (m.transmission == 0.0f) continue;
    ++panes;
    EXPECT_EQ(m.name, "glass");
    EXPECT_FLOAT_EQ(m.transmission, 1.0f);
    EXPECT_FLOAT_EQ(m.ior, 1.5f);
    EXPECT_TRUE(m.double_sided);
    EXPECT_EQ(m.kd, glm::vec3(0.0f));  // all pane, no opaque rest
  }
  EXPECT_EQ(panes, 1);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].kind, ScenePunctualLight::Kind::directional);
  EXPECT_EQ(s.emissive_triangles(), 0u);
}

}  // namespace
}  // namespace bp

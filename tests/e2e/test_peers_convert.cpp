// The peer harness's scene conventions (bench/peers/convert.py, issue 29) against bundlepath's own
// loader: the converter's peer-neutral description of a glTF file (camera, per material its
// triangles, area, front-facing vector area, bounds, emission and model with its parameters --
// glTF's metallic-roughness ones, or Phong's and Lambert's kd, ks, shininess --, the emitters' power,
// the punctual lights) must say what load_gltf reads from the same file. Runs the converter with the
// system python3 (standard library only); renders nothing and needs neither bpy nor pyluxcore.
#include "e2e/cli_runner.h"
#include "scene/gltf_loader.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace bp::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kSource = BP_SOURCE_DIR;

json describe(const std::string& scene, const std::string& dir) {
  const std::string out = dir + "/" + fs::path(scene).stem().string() + ".json";
  const CliResult r = run_shell("python3 '" + kSource + "/bench/peers/convert.py' describe '" + scene + "' '" + out + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out);
  if (!in) return json();
  return json::parse(in);
}

glm::vec3 vec(const json& j) { return glm::vec3(float(j.at(0)), float(j.at(1)), float(j.at(2))); }

void expect_near(const glm::vec3& a, const glm::vec3& b, float tol, const std::string& what) {
  EXPECT_LE(glm::length(a - b), tol) << what << ": converter (" << a.x << ", " << a.y << ", " << a.z
                                      << ") vs loader (" << b.x << ", " << b.y << ", " << b.z << ")";
}

// Everything the description states, checked against the loader's Scene.
void check_against_loader(const std::string& scene_path, const std::string& dir) {
  SCOPED_TRACE(scene_path);
  const json d = describe(scene_path, dir);
  ASSERT_TRUE(d.is_object());
  const Scene s = load_gltf(scene_path);
  const float size = glm::length(s.bounds.extent());
  const float tol = 1e-5f * size;

  const json& cam = d.at("camera");
  expect_near(vec(cam.at("position")), s.camera.position, tol, "camera position");
  expect_near(vec(cam.at("forward")), s.camera.forward, 1e-5f, "camera forward");
  expect_near(vec(cam.at("up")), s.camera.up, 1e-5f, "camera up");
  EXPECT_NEAR(double(cam.at("yfov")), s.camera.yfov, 1e-6);
  EXPECT_NEAR(double(cam.at("aspect")), s.camera.aspect, 1e-6);

  ASSERT_EQ(std::size_t(d.at("triangles")), s.triangles.size());
  expect_near(vec(d.at("bounds").at(0)), s.bounds.lo, tol, "scene bounds lo");
  expect_near(vec(d.at("bounds").at(1)), s.bounds.hi, tol, "scene bounds hi");

  const json& mats = d.at("materials");
  ASSERT_EQ(mats.size(), s.materials.size());
  struct Sum { std::size_t triangles = 0; double area = 0.0; glm::dvec3 vector_area{0.0}; Bounds bounds; };
  std::vector<Sum> sums(s.materials.size());
  for (const SceneTriangle& t : s.triangles) {
    Sum& m = sums.at(t.material);
    const glm::dvec3 e = glm::cross(glm::dvec3(t.p[1] - t.p[0]), glm::dvec3(t.p[2] - t.p[0]));
    ++m.triangles;
    m.area += 0.5 * glm::length(e);
    m.vector_area += 0.5 * e;
    for (const auto& p : t.p) m.bounds.grow(p);
  }
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const json& m = mats.at(i);
    const SceneMaterial& sm = s.materials[i];
    SCOPED_TRACE("material " + std::to_string(i) + " " + sm.name);
    EXPECT_EQ(std::size_t(m.at("triangles")), sums[i].triangles);
    EXPECT_NEAR(double(m.at("area")), sums[i].area, 1e-5 * (sums[i].area + 1e-9) + 1e-9);
    expect_near(vec(m.at("vector_area")), glm::vec3(sums[i].vector_area), 1e-5f * float(sums[i].area) + 1e-7f,
                "vector area (the side the front faces look to)");
    if (sums[i].triangles) {
      expect_near(vec(m.at("bounds").at(0)), sums[i].bounds.lo, tol, "bounds lo");
      expect_near(vec(m.at("bounds").at(1)), sums[i].bounds.hi, tol, "bounds hi");
    }
    // The material model as the loader reads it: glTF's metallic-roughness BRDF by its parameters
    // (the peers build Principled / glossy2 materials of them), Phong and Lambert by kd, ks, shininess.
    EXPECT_EQ(bool(m.at("ggx")), sm.ggx);
    if (sm.ggx) {
      EXPECT_EQ(std::string(m.at("model")), "ggx");
      expect_near(vec(m.at("base_color")), sm.base_color, 1e-6f, "base colour");
      EXPECT_NEAR(double(m.at("metallic")), sm.metallic, 1e-6);
      EXPECT_NEAR(double(m.at("roughness")), sm.roughness, 1e-6);
      expect_near(vec(m.at("dielectric_f0")), sm.dielectric_f0, 1e-6f, "dielectric f0");
      EXPECT_NEAR(double(m.at("specular_weight")), sm.specular_weight, 1e-6);
      EXPECT_EQ(bool(m.at("metallic_roughness_texture")), sm.textures.metallic_roughness != BP_NO_TEXTURE);
    } else {
      const bool lobe = glm::max(sm.ks.x, glm::max(sm.ks.y, sm.ks.z)) > 0.0f;
      EXPECT_EQ(std::string(m.at("model")), lobe ? "phong" : "lambert");
      expect_near(vec(m.at("kd")), sm.kd, 1e-6f, "kd");
      expect_near(vec(m.at("ks")), sm.ks, 1e-6f, "ks");
      if (lobe) {
        EXPECT_NEAR(double(m.at("shininess")), sm.shininess, 1e-6);
      }
    }
    expect_near(vec(m.at("emission")), sm.emission, 1e-5f * (glm::length(sm.emission) + 1.0f), "emission");
    EXPECT_EQ(bool(m.at("double_sided")), sm.double_sided);
    EXPECT_EQ(bool(m.at("textured")), sm.textured());
  }

  // Emitters: power = pi * sides * area * Le per channel, from the loader's triangles.
  std::size_t emitting = 0;
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const SceneMaterial& sm = s.materials[i];
    if (sums[i].triangles == 0 || glm::length(sm.emission) == 0.0f) continue;
    ++emitting;
    const json* found = nullptr;
    for (const json& e : d.at("emitters"))
      if (std::size_t(e.at("material")) == i) found = &e;
    ASSERT_NE(found, nullptr) << "emitter material " << i << " missing from the description";
    const double sides = sm.double_sided ? 2.0 : 1.0;
    const glm::vec3 power = float(M_PI * sides * sums[i].area) * sm.emission;
    expect_near(vec(found->at("power_w")), power, 1e-5f * glm::length(power), "emitter power (W)");
  }
  EXPECT_EQ(d.at("emitters").size(), emitting);

  const json& lights = d.at("lights");
  ASSERT_EQ(lights.size(), s.lights.size());
  for (std::size_t i = 0; i < s.lights.size(); ++i) {
    const json& l = lights.at(i);
    const ScenePunctualLight& sl = s.lights[i];
    SCOPED_TRACE("light " + std::to_string(i) + " " + sl.name);
    const char* kind = sl.kind == ScenePunctualLight::Kind::point ? "point"
                       : sl.kind == ScenePunctualLight::Kind::spot ? "spot"
                                                                    : "directional";
    EXPECT_EQ(std::string(l.at("kind")), kind);
    expect_near(vec(l.at("intensity")), sl.intensity, 1e-6f * glm::length(sl.intensity), "intensity");
    expect_near(vec(l.at("direction")), sl.direction, 1e-5f, "direction");
    if (sl.kind == ScenePunctualLight::Kind::directional) {
      expect_near(vec(l.at("irradiance")), sl.intensity, 1e-6f * glm::length(sl.intensity), "irradiance (W/m^2)");
      continue;
    }
    expect_near(vec(l.at("position")), sl.position, tol, "position");
    expect_near(vec(l.at("watts")), float(4.0 * M_PI) * sl.intensity, 1e-5f * glm::length(sl.intensity) * 13.0f,
                "watts (4 pi I)");
    if (sl.kind == ScenePunctualLight::Kind::spot) {
      EXPECT_NEAR(double(l.at("inner_cone")), sl.inner_cone, 1e-6);
      EXPECT_NEAR(double(l.at("outer_cone")), sl.outer_cone, 1e-6);
    }
  }
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = std::uint32_t(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= std::uint32_t(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= bytes[i + 2];
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? k[v & 63] : '=';
  }
  return out;
}

// A 2x2 RGB PNG of texels (0, 128, 255): a metallic-roughness texture (G roughness, B metallic).
const char* kMetallicRoughnessPng =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAD0lEQVR4nGNgaPgPQhAKACX2Bf2gcp/LAAAAAElFTkSuQmCC";

// A file that exercises what the shipped scenes do not: a node hierarchy of TRS and matrix
// transforms, a mirroring node, a triangle strip and fan, metallic-roughness materials (half metal;
// with KHR_materials_ior and KHR_materials_specular; with a metallicRoughnessTexture), a Phong one
// scaled to kd + ks = 1, a double-sided emitter, a spot light and a camera under a rotated parent.
std::string write_synthetic_scene(const std::string& dir) {
  std::vector<std::uint8_t> buf;
  auto put = [&](const void* p, std::size_t n) { buf.insert(buf.end(), (const std::uint8_t*)p, (const std::uint8_t*)p + n); };
  const float quad[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};     // 4 vertices, 48 bytes
  const std::uint16_t quad_idx[] = {0, 1, 2, 0, 2, 3};         // 12 bytes
  const float strip[] = {0, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0, 1, 2, 0.5f, 0};  // 5 vertices, 60 bytes
  put(quad, sizeof quad);
  put(quad_idx, sizeof quad_idx);
  put(strip, sizeof strip);
  const json gltf = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_materials_emissive_strength", "KHR_lights_punctual", "KHR_materials_ior",
                          "KHR_materials_specular"}},
      {"extensions", {{"KHR_lights_punctual", {{"lights", {{{"type", "spot"}, {"name", "spot"}, {"color", {1.0, 0.5, 0.25}},
                                                              {"intensity", 683.0},
                                                              {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
                                                             {{"type", "directional"}, {"name", "sun"}, {"intensity", 1000.0}}}}}}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 5}}}}},
      {"nodes",
       {{{"name", "parent"}, {"translation", {1.0, 2.0, 3.0}}, {"rotation", {0.0, 0.258819, 0.0, 0.9659258}},
         {"scale", {2.0, 1.0, 1.5}}, {"children", {1, 2, 3, 4}}},
        {{"name", "mirrored"}, {"mesh", 0}, {"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, 0, 1}}},
        {{"name", "spot"}, {"translation", {0.0, 3.0, 0.0}}, {"rotation", {-0.7071068, 0.0, 0.0, 0.7071068}},
         {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
        {{"name", "camera"}, {"camera", 0}, {"translation", {0.0, 1.0, 5.0}}, {"rotation", {-0.0871557, 0.0, 0.0, 0.9961947}}},
        {{"name", "strip"}, {"mesh", 1}, {"translation", {0.0, -1.0, 0.0}}},
        {{"name", "sun"}, {"rotation", {-0.3826834, 0.0, 0.0, 0.9238795}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}}}},
      {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"aspectRatio", 1.5}, {"znear", 0.01}}}}}},
      {"materials",
       {{{"name", "lambert"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.4, 0.3, 1.0}}, {"metallicFactor", 0.0}}}},
        {{"name", "lamp"}, {"doubleSided", true}, {"emissiveFactor", {1.0, 0.5, 0.25}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 5.0}}}}},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.2, 0.2, 1.0}}, {"metallicFactor", 0.0}}}},
        {{"name", "metal"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 0.9, 0.8, 1.0}}, {"metallicFactor", 0.5},
                                                        {"roughnessFactor", 0.4}}}},
        {{"name", "coated"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0.3, 0.6, 0.2, 1.0}}, {"metallicFactor", 0.25}, {"roughnessFactor", 0.7}}},
         {"extensions", {{"KHR_materials_ior", {{"ior", 1.8}}},
                         {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.8, 0.6}}}}}}},
        {{"name", "phong"}, {"extras", {{"phong", {{"kd", {0.3, 0.3, 0.2}}, {"ks", {0.8, 0.8, 0.8}}, {"shininess", 25.0}}}}}},
        {{"name", "textured metal"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.9, 0.9, 1.0}}, {"roughnessFactor", 0.6},
                                   {"metallicRoughnessTexture", {{"index", 0}}}}}}}},
      {"textures", {{{"source", 0}}}},
      {"images", {{{"uri", std::string("data:image/png;base64,") + kMetallicRoughnessPng}}}},
      {"meshes",
       {{{"name", "quad"}, {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}},
                                            {{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 2}}}}},
        {{"name", "strips"}, {"primitives", {{{"attributes", {{"POSITION", 2}}}, {"mode", 5}, {"material", 1}},
                                              {{"attributes", {{"POSITION", 2}}}, {"mode", 6}}}}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}},
        {{"bufferView", 2}, {"componentType", 5126}, {"count", 5}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {2, 0.5, 1}}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}},
                       {{"buffer", 0}, {"byteOffset", 60}, {"byteLength", 60}}}},
      {"buffers", {{{"byteLength", buf.size()}, {"uri", "data:application/octet-stream;base64," + base64(buf)}}}},
  };
  const std::string path = dir + "/synthetic.gltf";
  std::ofstream(path) << gltf.dump(1);
  return path;
}

TEST(PeersConvert, DescriptionMatchesTheLoaderOnTheShippedScenes) {
  const std::string dir = fresh_dir("peers-convert");
  for (const char* name : {"cornell-box.gltf", "cornell-glossy.gltf", "cornell-ggx.gltf", "blender-point-light.gltf",
                           "blender-room.glb"})
    check_against_loader(kSource + "/scenes/" + name, dir);
}

TEST(PeersConvert, DescriptionMatchesTheLoaderOnTransformsLightsEmittersAndMaterials) {
  const std::string dir = fresh_dir("peers-convert-synthetic");
  const std::string scene = write_synthetic_scene(dir);
  check_against_loader(scene, dir);
  // The file's content, as the peers are to render it (not only the agreement with the loader).
  const json d = describe(scene, dir);
  ASSERT_TRUE(d.is_object());
  ASSERT_EQ(d.at("emitters").size(), 1u);
  EXPECT_TRUE(bool(d.at("emitters").at(0).at("double_sided")));
  ASSERT_EQ(d.at("lights").size(), 2u);
  EXPECT_NEAR(double(d.at("lights").at(0).at("watts").at(0)), 4.0 * M_PI, 1e-6);  // 683 cd of white = 1 W/sr
  EXPECT_NEAR(double(d.at("lights").at(1).at("irradiance").at(1)), 1000.0 / 683.0, 1e-9);
  EXPECT_NEAR(double(d.at("camera").at("yfov")), 0.8, 1e-12);

  // The materials as the file writes them (index 0 is the default material, file material i is i + 1):
  // the metallic-roughness parameters the peers build their GGX materials from.
  const json& mats = d.at("materials");
  ASSERT_EQ(mats.size(), 7u);
  auto expect_rgb = [](const json& j, glm::vec3 v, const std::string& what) { expect_near(vec(j), v, 1e-6f, what); };
  const json& plastic = mats.at(1);  // "lambert": metallic 0, but the default specular 1 makes it glTF's GGX
  EXPECT_EQ(std::string(plastic.at("model")), "ggx");
  EXPECT_NEAR(double(plastic.at("metallic")), 0.0, 1e-12);
  EXPECT_NEAR(double(plastic.at("roughness")), 1.0, 1e-12);  // glTF's default
  const json& metal = mats.at(3);
  EXPECT_EQ(std::string(metal.at("model")), "ggx");
  expect_rgb(metal.at("base_color"), {1.0f, 0.9f, 0.8f}, "metal base colour");
  EXPECT_NEAR(double(metal.at("metallic")), 0.5, 1e-12);
  EXPECT_NEAR(double(metal.at("roughness")), 0.4, 1e-12);
  EXPECT_NEAR(double(metal.at("ior")), 1.5, 1e-12);  // KHR_materials_ior's default
  expect_rgb(metal.at("dielectric_f0"), glm::vec3(0.04f), "metal's dielectric f0");
  EXPECT_NEAR(double(metal.at("specular_weight")), 1.0, 1e-12);
  EXPECT_FALSE(bool(metal.at("metallic_roughness_texture")));
  const json& coated = mats.at(4);
  EXPECT_EQ(std::string(coated.at("model")), "ggx");
  expect_rgb(coated.at("base_color"), {0.3f, 0.6f, 0.2f}, "coated base colour");
  EXPECT_NEAR(double(coated.at("metallic")), 0.25, 1e-12);
  EXPECT_NEAR(double(coated.at("roughness")), 0.7, 1e-12);
  EXPECT_NEAR(double(coated.at("ior")), 1.8, 1e-12);
  EXPECT_NEAR(double(coated.at("specular_weight")), 0.5, 1e-12);
  expect_rgb(coated.at("specular_color"), {1.0f, 0.8f, 0.6f}, "specular colour");
  const float f0 = (0.8f / 2.8f) * (0.8f / 2.8f);  // ((ior - 1) / (ior + 1))^2
  expect_rgb(coated.at("dielectric_f0"), f0 * glm::vec3(1.0f, 0.8f, 0.6f), "coated dielectric f0");
  const json& phong = mats.at(5);
  EXPECT_EQ(std::string(phong.at("model")), "phong");
  EXPECT_FALSE(bool(phong.at("ggx")));
  expect_rgb(phong.at("kd"), glm::vec3(0.3f, 0.3f, 0.2f) / 1.1f, "phong kd (kd + ks = 1.1: scaled to 1)");
  expect_rgb(phong.at("ks"), glm::vec3(0.8f) / 1.1f, "phong ks (kd + ks = 1.1: scaled to 1)");
  EXPECT_NEAR(double(phong.at("shininess")), 25.0, 1e-12);
  const json& textured = mats.at(6);
  EXPECT_EQ(std::string(textured.at("model")), "ggx");
  EXPECT_TRUE(bool(textured.at("metallic_roughness_texture")));
  EXPECT_TRUE(bool(textured.at("textured")));
  EXPECT_NEAR(double(textured.at("metallic")), 1.0, 1e-12);  // glTF's default, the texture's B multiplies it
  EXPECT_NEAR(double(textured.at("roughness")), 0.6, 1e-12);
}

TEST(PeersConvert, UnusableFileIsRefused) {
  const std::string dir = fresh_dir("peers-convert-bad");
  std::ofstream(dir + "/bad.gltf") << "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": []}]}";
  const CliResult r = run_shell("python3 '" + kSource + "/bench/peers/convert.py' describe '" + dir + "/bad.gltf' '" + dir +
                                "/bad.json'");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("no triangles"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bp::test

// Inputs the loader's fuzz target (fuzz/fuzz_gltf_loader.cpp, scripts/fuzz.sh) or its crafted
// variants made hang, run out of memory or slip through; and the in-memory entry point it uses.
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace bp {
namespace {

using test::test_file;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Regression {
  const char* file;
  const char* object;  // part of the SceneError message
  const char* was;     // what the loader did before the fix
};

class FuzzRegression : public ::testing::TestWithParam<Regression> {};

// Refused with a one-line SceneError, quickly (the fuzzer's bar is 1 s per input, with sanitizers).
TEST_P(FuzzRegression, RefusedQuicklyWithOneLine) {
  const Regression& r = GetParam();
  const std::string path = test_file(std::string("bad/") + r.file);
  const auto start = std::chrono::steady_clock::now();
  try {
    load_gltf(path);
    FAIL() << "loaded " << r.file << " (was: " << r.was << ")";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(r.object), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 1.0) << r.file << " (was: " << r.was << ")";
}

INSTANTIATE_TEST_SUITE_P(
    All, FuzzRegression,
    ::testing::Values(
        Regression{"node-two-parents.gltf", "node 47 is reached twice",
                   "each node the two children of the one before: 2^47 mesh instances, a hang"},
        Regression{"scene-node-twice.gltf", "node 0 is reached twice", "the mesh instanced once per listing"},
        Regression{"sparse-huge-count.gltf", "has an implausible count 268435455",
                   "a 6 GB allocation for a view-less sparse accessor"},
        Regression{"camera-aspect-overflow.gltf", "has aspectRatio", "aspect 1e300 became an infinite float"}),
    [](const auto& info) { return bp::test::test_name_from_file(info.param.file); });

// The fuzz target's entry point gives what load_gltf gives, for every seed file.
TEST(GltfFromMemory, SameSceneAsFromFileForEverySeed) {
  int loaded = 0, refused = 0;
  for (const char* folder : {"good", "bad", "samples"}) {
    for (const auto& entry : std::filesystem::directory_iterator(test_file(folder))) {
      const std::string path = entry.path().string(), ext = entry.path().extension().string();
      if (ext != ".gltf" && ext != ".glb") continue;
      const std::string bytes = read_bytes(path);
      const bool glb = bytes.compare(0, 4, "glTF") == 0;
      std::string file_error, memory_error;
      Scene from_file, from_memory;
      try { from_file = load_gltf(path); } catch (const SceneError& e) { file_error = e.what(); }
      try { from_memory = load_gltf_from_memory(bytes, path, glb); } catch (const SceneError& e) { memory_error = e.what(); }
      // In memory there is no folder: a file that uses an external buffer is refused for that.
      const bool external = memory_error.find("is an external file") != std::string::npos;
      if (external) {
        ++refused;
        continue;
      }
      if (file_error.empty()) {
        ++loaded;
        ASSERT_EQ(memory_error, "") << path;
        ASSERT_EQ(from_memory.triangles.size(), from_file.triangles.size()) << path;
        for (std::size_t t = 0; t < from_file.triangles.size(); ++t)
          for (int k = 0; k < 3; ++k) ASSERT_EQ(from_memory.triangles[t].p[k], from_file.triangles[t].p[k]) << path;
        EXPECT_EQ(from_memory.materials.size(), from_file.materials.size()) << path;
        EXPECT_EQ(from_memory.source, path);
      } else {
        ++refused;
        EXPECT_EQ(memory_error, file_error) << path;
      }
    }
  }
  EXPECT_GT(loaded, 10);
  EXPECT_GT(refused, 20);
}

TEST(GltfFromMemory, RefusesExternalBuffersAndWrongFormat) {
  const std::string external = read_bytes(test_file("good/external-bin.gltf"));
  try {
    load_gltf_from_memory(external, "mem.gltf", false);
    FAIL() << "an external buffer was read from memory";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("mem.gltf: buffer 0 uri \"external-bin.bin\" is an external file"),
              std::string::npos) << e.what();
  }
  const std::string glb = read_bytes(test_file("good/triangle.glb"));
  EXPECT_EQ(load_gltf_from_memory(glb, "mem.glb", true).triangles.size(), 1u);
  EXPECT_THROW(load_gltf_from_memory(glb, "mem.glb", false), SceneError);  // binary read as JSON
  EXPECT_THROW(load_gltf_from_memory(external, "mem.gltf", true), SceneError);  // JSON read as binary
  EXPECT_THROW(load_gltf_from_memory("", "empty", false), SceneError);
  EXPECT_THROW(load_gltf_from_memory("glTF", "short", true), SceneError);
}

}  // namespace
}  // namespace bp

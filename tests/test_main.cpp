// GoogleTest main: every test process gets its own PoCL cache and kernel-binary cache under the
// build tree, named after the test it runs, so parallel ctest processes never share one.
#include <gtest/gtest.h>
#include <cstdlib>
#include <filesystem>
#include <string>

int main(int argc, char** argv) {
  std::string name = "all";
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.rfind("--gtest_filter=", 0) == 0) name = arg.substr(15);
  }
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  auto dir = std::filesystem::path(BP_BUILD_DIR) / "test-cache" / name;
  std::filesystem::create_directories(dir / "pocl");
  setenv("POCL_CACHE_DIR", (dir / "pocl").c_str(), 1);
  setenv("BUNDLEPATH_CACHE_DIR", (dir / "kernels").c_str(), 1);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

// Kernel programs: include assembly, the persistent binary cache, and build errors that name the
// real file and line.
#include "kernel/device_fixture.h"

#include "device/kernel_source.h"
#include "device/program_cache.h"

#include <gtest/gtest.h>
#include <cstdlib>
#include <filesystem>

namespace bp::test {
namespace {

TEST(KernelSource, IncludesAreInlinedOnceWithLineDirectives) {
  std::string src = assemble_kernel_source("pathtrace.cl");
  EXPECT_NE(src.find("#line 1 \"kernels/shared/compat.h\""), std::string::npos);
  EXPECT_NE(src.find("#line 1 \"kernels/pathtrace.cl\""), std::string::npos);
  std::size_t first = src.find("#line 1 \"kernels/shared/compat.h\"");
  EXPECT_EQ(src.find("#line 1 \"kernels/shared/compat.h\"", first + 1), std::string::npos) << "compat.h inlined twice";
  EXPECT_EQ(src.find("#include \"shared/"), std::string::npos);
  EXPECT_THROW(assemble_kernel_source("no_such_kernel.cl"), std::runtime_error);
}

TEST(ProgramCache, SecondBuildComesFromTheCacheAndKeysSeparateOptions) {
  auto dir = std::filesystem::path(BP_BUILD_DIR) / "test-out" / "program_cache";
  std::filesystem::remove_all(dir);
  setenv("BUNDLEPATH_CACHE_DIR", dir.c_str(), 1);
  const DeviceContext& device = test_device();
  BuiltProgram cold = build_program(device, "test/sampling_test.cl");
  EXPECT_FALSE(cold.from_cache);
  BuiltProgram warm = build_program(device, "test/sampling_test.cl");
  EXPECT_TRUE(warm.from_cache);
  cl::Kernel kernel(warm.program, "sample_bsdf");  // the cached binary is usable
  BuiltProgram other = build_program(device, "test/sampling_test.cl", "-DBP_UNUSED_OPTION=1");
  EXPECT_FALSE(other.from_cache) << "different options must not share a cache entry";

  // A corrupt entry is rebuilt from source, not fatal.
  for (const auto& e : std::filesystem::directory_iterator(dir)) std::filesystem::resize_file(e.path(), 7);
  BuiltProgram rebuilt = build_program(device, "test/sampling_test.cl");
  EXPECT_FALSE(rebuilt.from_cache);
  EXPECT_TRUE(build_program(device, "test/sampling_test.cl").from_cache);
}

TEST(ProgramCache, KeyDependsOnSourceOptionsAndDevice) {
  DeviceInfo a = test_device().info, b = a;
  b.driver_version += "x";
  EXPECT_NE(kernel_cache_key("s", "o", a), kernel_cache_key("s", "o", b));
  EXPECT_NE(kernel_cache_key("s", "o", a), kernel_cache_key("s2", "o", a));
  EXPECT_NE(kernel_cache_key("s", "o", a), kernel_cache_key("s", "o2", a));
  EXPECT_EQ(kernel_cache_key("s", "o", a), kernel_cache_key("s", "o", a));
}

TEST(ProgramCache, BuildErrorNamesTheRealFileAndLine) {
  try {
    build_program(test_device(), "test/sampling_test.cl", "-DBP_TEST_BUILD_ERROR");
    FAIL() << "the build should have failed";
  } catch (const DeviceError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("kernels/test/sampling_test.cl:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("this_line_does_not_compile"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace bp::test

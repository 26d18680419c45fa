// A render on cold kernel caches prints nothing but its own lines: what the OpenCL compiler says while
// building (PoCL's "1 warning generated.") goes to --verbose, and into the error when a build fails.
#include "e2e/cli_runner.h"

#include <gtest/gtest.h>
#include <sstream>
#include <string>

namespace bp::test {
namespace {

// The ray-bundle kernels of the glossy box, built from source: PoCL's and our caches both empty.
CliResult cold_render(const std::string& dir, const std::string& extra) {
  const std::string env = "BUNDLEPATH_CACHE_DIR='" + dir + "/kernels' POCL_CACHE_DIR='" + dir + "/pocl'";
  return run_cli("render '" + std::string(BP_SOURCE_DIR) + "/scenes/cornell-glossy.gltf' --mode rb --iterations 4 " +
                     "--width 16 --height 16 --out '" + dir + "/img' " + extra,
                 env);
}

TEST(BuildLog, ColdKernelBuildsAreQuietUnlessVerbose) {
  const CliResult quiet = cold_render(fresh_dir("build_log_quiet"), "");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  std::istringstream lines(quiet.output);
  for (std::string line; std::getline(lines, line);)
    EXPECT_EQ(line.rfind("bundlepath: ", 0), 0u) << "a line that is not the renderer's: " << line << "\n" << quiet.output;
  EXPECT_EQ(quiet.output.find("compiler output"), std::string::npos) << quiet.output;

  const CliResult verbose = cold_render(fresh_dir("build_log_verbose"), "--verbose");
  ASSERT_EQ(verbose.exit_code, 0) << verbose.output;
  EXPECT_NE(verbose.output.find("bundlepath: built kernels/bundle.cl on "), std::string::npos) << verbose.output;
  EXPECT_NE(verbose.output.find("compiler output:"), std::string::npos) << verbose.output;
}

}  // namespace
}  // namespace bp::test

// Runs the real `bundlepath` binary for end-to-end tests.
#pragma once
#include <string>

namespace bp::test {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// `env` is prepended to the command line (e.g. "OCL_ICD_VENDORS=/nonexistent").
CliResult run_cli(const std::string& args, const std::string& env = "");

// Runs a /bin/sh command line, capturing stdout and stderr.
CliResult run_shell(const std::string& command);

// A fresh empty directory for one test's outputs.
std::string fresh_dir(const std::string& name);

}  // namespace bp::test

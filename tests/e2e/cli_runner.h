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

// Runs a render command line (stderr to DIR/log), sends it one SIGINT once its render loop has
// started (its "rendering" line), with a hard bound of 120 s on the child, and gives "exit=CODE"
// and the log. (Not through `timeout`: it forwards a signal to its child and to its process group,
// so the renderer could get two SIGINTs, and the second one means "abort now".)
CliResult interrupt_once_started(const std::string& render_command, const std::string& dir);

// A fresh empty directory for one test's outputs.
std::string fresh_dir(const std::string& name);

}  // namespace bp::test

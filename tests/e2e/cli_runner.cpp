#include "e2e/cli_runner.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <sys/wait.h>

namespace bp::test {

CliResult run_cli(const std::string& args, const std::string& env) {
  return run_shell(env + (env.empty() ? "" : " ") + "'" + BP_BINARY + "' " + args);
}

CliResult run_shell(const std::string& command_line) {
  std::string command = "(" + command_line + ") 2>&1";
  CliResult r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

CliResult interrupt_once_started(const std::string& render_command, const std::string& dir) {
  return run_shell(render_command + " 2>" + dir + "/log & pid=$!; (sleep 120; kill -KILL $pid) >/dev/null 2>&1 & " +
                   "watchdog=$!; for i in $(seq 600); do grep -q rendering " + dir +
                   "/log && break; sleep 0.1; done; sleep 1; kill -INT $pid; wait $pid; echo \"exit=$?\"; " +
                   "kill $watchdog 2>/dev/null; cat " + dir + "/log");
}

std::string fresh_dir(const std::string& name) {
  auto dir = std::filesystem::path(BP_BUILD_DIR) / "test-out" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace bp::test

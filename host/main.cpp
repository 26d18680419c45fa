// bundlepath: CLI -> scene -> device -> passes -> image. The only place that maps failures to exit codes.
#include "cli/commands.h"
#include "cli/options.h"
#include "device/opencl.h"
#include "device/program_cache.h"
#include "render/ranks.h"
#include "scene/gltf_loader.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace {

// One line and the exit code. On several MPI ranks the failure may be this rank's alone, with the
// others waiting for it: every rank ends with this code, and a rank other than 0 names itself. Before
// the job is joined (the command line, alike on every rank) rank 0 alone says it.
int fail(const std::optional<bp::RankSession>& session, const std::exception& e, int exit_code) {
  if (!session && bp::launched_rank() != 0) return exit_code;
  const bool several_ranks = session && session->ranks().size() > 1;
  const std::string rank = several_ranks && !session->ranks().root()
                               ? "rank " + std::to_string(session->ranks().rank()) + ": "
                               : "";
  std::fprintf(stderr, "bundlepath: %s%s\n", rank.c_str(), e.what());
  if (several_ranks) session->abort(exit_code);
  return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::optional<bp::RankSession> session;  // render: the MPI job when mpirun started this process
  try {
    if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
      std::fputs(bp::main_help(), args.empty() ? stderr : stdout);
      return args.empty() ? 2 : 0;
    }
    if (args[0] == "--version") return bp::run_version();
    const std::string command = args[0];
    std::vector<std::string> rest(args.begin() + 1, args.end());
    for (const std::string& a : rest) {
      if (a == "-h" || a == "--help") {
        std::fputs(command == "render" ? bp::render_help() : bp::main_help(), stdout);
        return 0;
      }
      if (a == "--help-all") {
        std::fputs(command == "render" ? bp::render_help_all() : bp::main_help(), stdout);
        return 0;
      }
    }
    // The commands: what runs each; an unknown command's message lists them, in this order.
    const std::vector<std::pair<std::string, std::function<int()>>> commands = {
        {"render",
         [&] {
           // --verbose says only how much the kernel builds print; the render's options are the rest.
           if (const auto v = std::remove(rest.begin(), rest.end(), "--verbose"); v != rest.end()) {
             bp::set_verbose_kernel_builds(true);
             rest.erase(v, rest.end());
           }
           const bp::RenderOptions options = bp::parse_render_options(rest);
           session.emplace();
           return bp::run_render(options, session->ranks());
         }},
        {"devices",
         [&] {
           if (!rest.empty()) throw bp::UsageError("devices takes no arguments");
           return bp::run_devices();
         }},
        {"compare", [&] { return bp::run_compare(rest); }},
    };
    std::string names;
    for (const auto& [name, run] : commands) {
      if (name == command) return run();
      names += (names.empty() ? "" : ", ") + name;
    }
    throw bp::UsageError("unknown command '" + command + "' (commands: " + names + "; see --help)");
  } catch (const bp::UsageError& e) {
    return fail(session, e, 2);
  } catch (const bp::NoPlatformError& e) {
    return fail(session, e, 2);
  } catch (const bp::SceneError& e) {
    return fail(session, e, 3);
  } catch (const std::exception& e) {
    return fail(session, e, 1);
  }
}

// bundlepath: CLI -> scene -> device -> passes -> image. The only place that maps failures to exit codes.
#include "cli/commands.h"
#include "cli/options.h"
#include "device/opencl.h"
#include "scene/gltf_loader.h"

#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
      std::fputs(bp::main_help(), args.empty() ? stderr : stdout);
      return args.empty() ? 2 : 0;
    }
    if (args[0] == "--version") {
      std::printf("bundlepath %s\n", BUNDLEPATH_VERSION);
      return 0;
    }
    const std::string command = args[0];
    std::vector<std::string> rest(args.begin() + 1, args.end());
    for (const std::string& a : rest)
      if (a == "-h" || a == "--help") {
        std::fputs(command == "render" ? bp::render_help() : bp::main_help(), stdout);
        return 0;
      }
    if (command == "devices") {
      if (!rest.empty()) throw bp::UsageError("devices takes no arguments");
      return bp::run_devices();
    }
    if (command == "render") return bp::run_render(bp::parse_render_options(rest));
    if (command == "compare") return bp::run_compare(rest);
    throw bp::UsageError("unknown command '" + command + "' (commands: render, devices; see --help)");
  } catch (const bp::UsageError& e) {
    std::fprintf(stderr, "bundlepath: %s\n", e.what());
    return 2;
  } catch (const bp::NoPlatformError& e) {
    std::fprintf(stderr, "bundlepath: %s\n", e.what());
    return 2;
  } catch (const bp::SceneError& e) {
    std::fprintf(stderr, "bundlepath: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bundlepath: %s\n", e.what());
    return 1;
  }
}

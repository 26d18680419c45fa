#include "device/program_cache.h"
#include "device/kernel_source.h"
#include "image/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <mutex>

namespace bp {
namespace {

std::uint64_t fnv1a(std::uint64_t h, const std::string& s) {
  for (unsigned char c : s) { h ^= c; h *= 0x100000001b3ull; }
  h ^= 0xff;  // field separator, so ("ab","c") and ("a","bc") differ
  h *= 0x100000001b3ull;
  return h;
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string build_log(const cl::Program& program, const cl::Device& device) {
  try {
    return program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
  } catch (const cl::Error&) {
    return "(no build log available)";
  }
}

std::atomic<bool> verbose_builds{false};

// The process's stderr (fd 2) sent to a temporary file while a program builds from source: PoCL's
// compiler prints its summary ("1 warning generated.") there, beside the build log. One capture at
// a time (fd 2 is the process's), so builds from source on several devices take turns.
class StderrCapture {
 public:
  StderrCapture() : lock_(mutex()) {
    std::fflush(stderr);
    file_ = std::tmpfile();
    if (!file_) return;
    saved_ = ::dup(2);
    if (saved_ < 0 || ::dup2(::fileno(file_), 2) < 0) {
      if (saved_ >= 0) ::close(saved_);
      std::fclose(file_);
      file_ = nullptr;
    }
  }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  ~StderrCapture() { finish(); }

  // Puts stderr back and returns what was written to it meanwhile.
  std::string finish() {
    if (!file_) return {};
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
    std::string text;
    std::rewind(file_);
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, file_)) > 0;) text.append(buf, n);
    std::fclose(file_);
    file_ = nullptr;
    return text;
  }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

// The compiler's own output and the device's build log, for an error message or --verbose.
std::string compiler_messages(const std::string& captured, const std::string& log) {
  std::string text = captured;
  if (!text.empty() && text.back() != '\n') text += '\n';
  text += log;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text.empty() ? "(none)" : text;
}

}  // namespace

void set_verbose_kernel_builds(bool verbose) { verbose_builds = verbose; }

std::filesystem::path kernel_cache_dir() {
  if (const char* dir = std::getenv("BUNDLEPATH_CACHE_DIR")) {
    if (std::string(dir) == "off") return {};
    return dir;
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "bundlepath" / "kernels";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "bundlepath" / "kernels";
  return {};
}

std::string kernel_cache_key(const std::string& source, const std::string& options, const DeviceInfo& device) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const std::string* s : {&source, &options, &device.platform_name, &device.device_name,
                               &device.device_version, &device.driver_version})
    h = fnv1a(h, *s);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

BuiltProgram build_program(const DeviceContext& dc, const std::string& main_file, const std::string& extra_options) {
  auto start = std::chrono::steady_clock::now();
  const std::string source = assemble_kernel_source(main_file);
  const std::string options = "-cl-std=CL1.2 " + extra_options;
  const std::filesystem::path dir = kernel_cache_dir();
  const std::filesystem::path cached =
      dir.empty() ? std::filesystem::path() : dir / (kernel_cache_key(source, options, dc.info) + ".bin");
  BuiltProgram result;

  if (!cached.empty() && std::filesystem::exists(cached)) {
    std::string bytes = read_file(cached);
    try {
      cl::Program::Binaries binaries{std::vector<unsigned char>(bytes.begin(), bytes.end())};
      std::vector<cl_int> status;
      cl::Program program(dc.context, {dc.info.device}, binaries, &status);
      program.build({dc.info.device}, options.c_str());
      result.program = program;
      result.from_cache = true;
    } catch (const cl::Error&) {
      std::error_code ec;
      std::filesystem::remove(cached, ec);  // stale or corrupt: rebuild from source below
    }
  }

  if (!result.from_cache) {
    cl::Program program(dc.context, source);
    StderrCapture capture;
    try {
      program.build({dc.info.device}, options.c_str());
    } catch (const cl::BuildError&) {
      const std::string captured = capture.finish();
      throw DeviceError("kernel build of kernels/" + main_file + " failed on " + dc.info.device_name +
                        " (options: " + options + "):\n" +
                        compiler_messages(captured, build_log(program, dc.info.device)));
    } catch (const cl::Error& e) {
      const std::string captured = capture.finish();
      throw DeviceError("kernel build of kernels/" + main_file + " failed on " + dc.info.device_name + ": " +
                        cl_error_name(e.err()) + "\n" + compiler_messages(captured, build_log(program, dc.info.device)));
    }
    const std::string captured = capture.finish();
    if (verbose_builds) {
      std::fprintf(stderr, "bundlepath: built kernels/%s on %s (options: %s); compiler output:\n%s\n",
                   main_file.c_str(), dc.info.device_name.c_str(), options.c_str(),
                   compiler_messages(captured, build_log(program, dc.info.device)).c_str());
    }
    result.program = program;
    if (!cached.empty()) {
      try {
        auto binaries = program.getInfo<CL_PROGRAM_BINARIES>();
        if (binaries.size() == 1 && !binaries[0].empty()) {
          std::filesystem::create_directories(cached.parent_path());
          write_file_atomically(cached.string(), "kernel cache entry", [&](const std::string& tmp) {
            std::ofstream out(tmp, std::ios::binary);
            out.write(reinterpret_cast<const char*>(binaries[0].data()), std::streamsize(binaries[0].size()));
            if (!out) throw std::runtime_error("cannot write " + tmp);
          });
        }
      } catch (const std::exception&) {
        // the cache is an optimisation: a device without binaries or an unwritable cache runs uncached
      }
    }
  }
  result.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace bp

#include "image/denoiser.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

namespace bp {
namespace {
// The part of OIDN's C API (oidn.h, 2.x) used here, declared from its documentation.
using OIDNDevice = void*;
using OIDNFilter = void*;
constexpr int kDeviceTypeCpu = 1;   // OIDN_DEVICE_TYPE_CPU
constexpr int kFormatFloat3 = 3;    // OIDN_FORMAT_FLOAT3
constexpr int kQualityHigh = 6;     // OIDN_QUALITY_HIGH (final frames)
constexpr int kErrorNone = 0;       // OIDN_ERROR_NONE
// Where `cmake --install` puts scripts/setup.sh's copy, under the prefix (CMakeLists.txt).
constexpr const char* kInstalledLibrary = "lib/bundlepath/oidn/lib/libOpenImageDenoise.so.2";

std::string library_in(const std::string& place) {
  namespace fs = std::filesystem;
  std::error_code ec;
  return fs::is_directory(place, ec) ? (fs::path(place) / "libOpenImageDenoise.so.2").string() : place;
}
}  // namespace

struct Denoiser::Api {
  OIDNDevice (*new_device)(int type);
  void (*commit_device)(OIDNDevice);
  void (*release_device)(OIDNDevice);
  int (*get_device_int)(OIDNDevice, const char*);
  int (*get_device_error)(OIDNDevice, const char**);
  OIDNFilter (*new_filter)(OIDNDevice, const char*);
  void (*set_shared_filter_image)(OIDNFilter, const char*, void*, int, std::size_t, std::size_t, std::size_t,
                                  std::size_t, std::size_t);
  void (*set_filter_bool)(OIDNFilter, const char*, bool);
  void (*set_filter_int)(OIDNFilter, const char*, int);
  void (*commit_filter)(OIDNFilter);
  void (*execute_filter)(OIDNFilter);
  void (*release_filter)(OIDNFilter);
};

std::vector<std::string> denoiser_search_paths() {
  // Set, the variable is the one place: a user's choice is not overridden by a copy elsewhere.
  if (const char* env = std::getenv("BUNDLEPATH_OIDN_LIBRARY"); env && *env) return {library_in(env)};
  std::vector<std::string> places;
  // An installed bundlepath's own copy (cmake --install puts it beside the binary's prefix).
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) places.push_back((exe.parent_path() / ".." / kInstalledLibrary).lexically_normal().string());
#ifdef BUNDLEPATH_OIDN_DEFAULT_LIBRARY
  places.push_back(BUNDLEPATH_OIDN_DEFAULT_LIBRARY);
#endif
  places.push_back("libOpenImageDenoise.so.2");  // the system's library path
  return places;
}

std::unique_ptr<Denoiser> Denoiser::open() {
  std::string tried;
  for (const std::string& place : denoiser_search_paths()) {
    void* handle = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      tried += (tried.empty() ? "" : "; ") + place + ": " + (why ? why : "cannot open");
      continue;
    }
    auto api = std::make_unique<Api>();
    bool complete = true;
    auto bind = [&](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(handle, name));
      complete = complete && fn;
    };
    bind(api->new_device, "oidnNewDevice");
    bind(api->commit_device, "oidnCommitDevice");
    bind(api->release_device, "oidnReleaseDevice");
    bind(api->get_device_int, "oidnGetDeviceInt");
    bind(api->get_device_error, "oidnGetDeviceError");
    bind(api->new_filter, "oidnNewFilter");
    bind(api->set_shared_filter_image, "oidnSetSharedFilterImage");
    bind(api->set_filter_bool, "oidnSetFilterBool");
    bind(api->set_filter_int, "oidnSetFilterInt");
    bind(api->commit_filter, "oidnCommitFilter");
    bind(api->execute_filter, "oidnExecuteFilter");
    bind(api->release_filter, "oidnReleaseFilter");
    if (!complete) {
      dlclose(handle);
      tried += (tried.empty() ? "" : "; ") + place + ": not OpenImageDenoise 2 (a function of its API is missing)";
      continue;
    }
    return std::unique_ptr<Denoiser>(new Denoiser(handle, place, std::move(api)));
  }
  throw DenoiserUnavailable(
      "--denoise needs OpenImageDenoise 2 (libOpenImageDenoise.so.2), which was not found (" + tried +
      "): install it with `bash scripts/setup.sh --oidn` (the official runtime from PyPI's pyoidn, beside the "
      "build, where it is found without a rebuild), or set BUNDLEPATH_OIDN_LIBRARY to the library or its folder");
}

Denoiser::Denoiser(void* handle, std::string path, std::unique_ptr<Api> api)
    : handle_(handle), path_(std::move(path)), api_(std::move(api)) {
  device_ = api_->new_device(kDeviceTypeCpu);
  const char* message = nullptr;
  if (device_) api_->commit_device(device_);
  if (!device_ || api_->get_device_error(device_, &message) != kErrorNone) {
    std::string why = message ? message : "no device";
    if (device_) api_->release_device(device_);
    dlclose(handle_);
    throw DenoiserUnavailable("OpenImageDenoise (" + path_ + ") could not open its CPU device: " + why);
  }
  version_ = api_->get_device_int(device_, "version");
}

Denoiser::~Denoiser() {
  if (device_) api_->release_device(device_);
  // The library stays loaded: OIDN's thread pool may still be winding down.
}

void Denoiser::run(const char* what, const ImageRGB& input, const ImageRGB* albedo, const ImageRGB* normal, bool hdr,
                   bool clean_aux, ImageRGB& output) const {
  output = ImageRGB(input.width, input.height);
  OIDNFilter filter = api_->new_filter(device_, "RT");
  auto image = [&](const char* name, const ImageRGB& img) {
    api_->set_shared_filter_image(filter, name, const_cast<float*>(img.rgb.data()), kFormatFloat3,
                                  std::size_t(img.width), std::size_t(img.height), 0, 0, 0);
  };
  image(what, input);
  if (albedo) image("albedo", *albedo);
  if (normal) image("normal", *normal);
  image("output", output);
  if (hdr) api_->set_filter_bool(filter, "hdr", true);
  if (clean_aux) api_->set_filter_bool(filter, "cleanAux", true);
  api_->set_filter_int(filter, "quality", kQualityHigh);
  api_->commit_filter(filter);
  api_->execute_filter(filter);
  api_->release_filter(filter);
  const char* message = nullptr;
  if (api_->get_device_error(device_, &message) != kErrorNone)
    throw std::runtime_error(std::string("OpenImageDenoise failed on the ") + what + " image: " +
                             (message ? message : "unknown error"));
}

void Denoiser::prefilter(ImageRGB& albedo, ImageRGB& normal) const {
  ImageRGB out;
  if (!albedo.rgb.empty()) {
    run("albedo", albedo, nullptr, nullptr, false, false, out);
    albedo = std::move(out);
  }
  if (!normal.rgb.empty()) {
    run("normal", normal, nullptr, nullptr, false, false, out);
    normal = std::move(out);
  }
}

ImageRGB Denoiser::denoise(const ImageRGB& beauty, const ImageRGB& albedo, const ImageRGB& normal) const {
  const bool has_albedo = !albedo.rgb.empty(), has_normal = has_albedo && !normal.rgb.empty();
  ImageRGB out;
  run("color", beauty, has_albedo ? &albedo : nullptr, has_normal ? &normal : nullptr, true, has_albedo, out);
  return out;
}

}  // namespace bp

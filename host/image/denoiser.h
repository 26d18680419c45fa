// OpenImageDenoise (Apache-2.0), loaded at run time: its "RT" filter on the beauty with first-hit
// albedo and normal, the auxiliary images prefiltered first as Cycles does (docs/design.md §13).
//
// Why loaded and not linked: Debian 12 has no OIDN package, and the official runtime (the PyPI wheel
// pyoidn, scripts/setup.sh) ships no headers. So the build needs nothing of it, every mode works
// without it, and the few C functions used here are declared from OIDN's documented API.
#pragma once
#include "image/image.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace bp {

// The library could not be found or opened; the message says what to install.
class DenoiserUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Denoiser {
 public:
  // Opens the library: $BUNDLEPATH_OIDN_LIBRARY (a file or its folder) where set, and nothing else;
  // else an installed bundlepath's copy (PREFIX/lib/bundlepath/oidn), the copy scripts/setup.sh
  // --oidn put in .deps/oidn (compiled in), then
  // libOpenImageDenoise.so.2 on the system's library path. Throws DenoiserUnavailable naming each
  // place it looked.
  static std::unique_ptr<Denoiser> open();
  ~Denoiser();
  Denoiser(const Denoiser&) = delete;
  Denoiser& operator=(const Denoiser&) = delete;

  // Where the library was found, and OIDN's version (e.g. 20501).
  const std::string& library_path() const { return path_; }
  int version() const { return version_; }

  // The auxiliary images as OIDN wants them beside a noisy beauty: each denoised by the filter alone
  // (OIDN's "prefiltering"), so that the beauty's filter can trust them (cleanAux). Either may be
  // empty (no such image). Throws std::runtime_error with OIDN's message.
  void prefilter(ImageRGB& albedo, ImageRGB& normal) const;
  // The denoised beauty (HDR, linear), given prefiltered albedo and normal (either may be empty:
  // then the colour alone, and without albedo no normal). Throws std::runtime_error.
  ImageRGB denoise(const ImageRGB& beauty, const ImageRGB& albedo, const ImageRGB& normal) const;

 private:
  struct Api;
  Denoiser(void* handle, std::string path, std::unique_ptr<Api> api);
  void run(const char* what, const ImageRGB& input, const ImageRGB* albedo, const ImageRGB* normal, bool hdr,
           bool clean_aux, ImageRGB& output) const;
  void* handle_ = nullptr;
  std::string path_;
  std::unique_ptr<Api> api_;
  void* device_ = nullptr;
  int version_ = 0;
};

// The places Denoiser::open looks, in order (for its message and `bundlepath --version`).
std::vector<std::string> denoiser_search_paths();

}  // namespace bp

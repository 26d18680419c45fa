// bundlepath devices, compare and --version (render lives in render_command.cpp).
#include "cli/commands.h"

#include "device/device_context.h"
#include "image/denoiser.h"
#include "image/image.h"
#include "image/video.h"

#include <nlohmann/json.hpp>
#include <cstdio>
#include <memory>

namespace bp {

int run_devices() {
  for (const DeviceInfo& d : list_devices()) {
    std::printf("[%d] %s  (%s; %s; driver %s; %u compute units; %llu MiB)\n", d.index, d.device_name.c_str(),
                d.platform_name.c_str(), d.is_gpu ? "GPU" : "CPU", d.driver_version.c_str(), d.compute_units,
                static_cast<unsigned long long>(d.global_memory_bytes >> 20));
  }
  return 0;
}

int run_version() {
  std::printf("bundlepath %s\n", BUNDLEPATH_VERSION);
  // The optional parts, as a render would find them now.
  try {
    const std::unique_ptr<Denoiser> oidn = Denoiser::open();
    std::printf("  --denoise: OpenImageDenoise %d.%d.%d, %s\n", oidn->version() / 10000, oidn->version() / 100 % 100,
                oidn->version() % 100, oidn->library_path().c_str());
  } catch (const std::exception&) {
    std::printf("  --denoise: OpenImageDenoise not found (bash scripts/setup.sh --oidn, or BUNDLEPATH_OIDN_LIBRARY)\n");
  }
  const std::string mpi = mpi_library();
  std::printf("  MPI ranks: %s\n", mpi.empty() ? "not built in (install libopenmpi-dev and rebuild)" : mpi.c_str());
  std::printf("  --video: %s\n", ffmpeg_on_path() ? "ffmpeg found on PATH" : "ffmpeg not on PATH");
  return 0;
}

int run_compare(const std::vector<std::string>& args) {
  std::vector<std::string> files;
  std::string layer;
  bool json = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--json") json = true;
    else if (args[i] == "--layer") {
      if (i + 1 >= args.size()) throw UsageError("--layer: missing value");
      layer = args[++i];
    } else if (args[i].rfind("--", 0) == 0) throw UsageError("unknown option '" + args[i] + "' for compare");
    else files.push_back(args[i]);
  }
  if (files.size() != 2) throw UsageError("usage: bundlepath compare IMAGE.exr REFERENCE.exr [--layer NAME] [--json]");
  ImageRGB image = read_exr(files[0], layer), reference = read_exr(files[1]);
  if (image.width != reference.width || image.height != reference.height)
    throw UsageError(files[0] + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) + " but " +
                     files[1] + " is " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
  ErrorMetrics m = compare_images(image, reference);
  const double level = m.reference_mean != 0.0 ? m.reference_mean : 1.0;
  if (json) {
    nlohmann::json out = {{"rel_mse", m.rel_mse}, {"rmse", m.rmse}, {"mean_bias", m.mean_bias},
                          {"mean_abs_difference", m.mean_abs_difference}, {"reference_mean", m.reference_mean},
                          {"relative_bias", m.mean_bias / level},
                          {"relative_mean_abs_difference", m.mean_abs_difference / level}};
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("relMSE %.4g  RMSE %.4g  bias %+.4g (%+.2f %%)  mean |difference| %.4g (%.2f %% of the mean)\n",
                m.rel_mse, m.rmse, m.mean_bias, 100.0 * m.mean_bias / level, m.mean_abs_difference,
                100.0 * m.mean_abs_difference / level);
  }
  return 0;
}

}  // namespace bp

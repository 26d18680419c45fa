#include "scene/environment_map.h"

#include "image/image.h"
#include "kernels/shared/environment_map.h"
#include "scene/gltf_loader.h"

#include <cmath>
#include <filesystem>
#include <fstream>

namespace bp {
namespace {

double luminance(const float* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }  // Rec. 709

// cdf[0] = 0, cdf[n] = 1 over n weights (all zero: uniform, never chosen by a zero marginal anyway).
void append_cdf(const std::vector<double>& weights, std::vector<float>& out) {
  double total = 0.0;
  for (double w : weights) total += w;
  double running = 0.0;
  out.push_back(0.0f);
  for (std::size_t i = 0; i < weights.size(); ++i) {
    running += total > 0.0 ? weights[i] : 1.0;
    const double denominator = total > 0.0 ? total : double(weights.size());
    out.push_back(i + 1 == weights.size() ? 1.0f : float(running / denominator));
  }
}

}  // namespace

EnvironmentImage load_environment_exr(const std::string& path) {
  const auto fail = [&](const std::string& why) { return SceneError(path + ": environment map: " + why); };
  if (!std::filesystem::is_regular_file(path)) throw fail("no such file");
  {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);  // OpenEXR's magic number 76 2f 31 01
    if (!in || magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 || magic[3] != 0x01)
      throw fail("not an OpenEXR file");
  }
  ImageRGB image;
  try {
    image = read_exr(path);
  } catch (const std::exception& e) {
    throw fail(std::string("cannot read its R,G,B: ") + e.what());
  }
  if (image.width <= 0 || image.height <= 0) throw fail("the image is empty");
  if (image.width > kEnvironmentMaxWidth || image.height > kEnvironmentMaxHeight)
    throw fail(std::to_string(image.width) + "x" + std::to_string(image.height) + " is beyond the limit of " +
               std::to_string(kEnvironmentMaxWidth) + "x" + std::to_string(kEnvironmentMaxHeight));
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    if (!std::isfinite(image.rgb[i]) || image.rgb[i] < 0.0f) {
      const std::size_t texel = i / 3;
      throw fail("texel (" + std::to_string(texel % std::size_t(image.width)) + ", " +
                 std::to_string(texel / std::size_t(image.width)) + ") is " + std::to_string(image.rgb[i]) +
                 ": radiance must be finite and >= 0");
    }
  EnvironmentImage map;
  map.width = image.width;
  map.height = image.height;
  map.rgb = std::move(image.rgb);
  return map;
}

EnvironmentImage uniform_environment(const glm::vec3& radiance) {
  EnvironmentImage map;
  if (!(radiance.x > 0.0f || radiance.y > 0.0f || radiance.z > 0.0f)) return map;
  map.width = map.height = 1;
  map.rgb = {radiance.x, radiance.y, radiance.z};
  return map;
}

double environment_sampling_weight(const EnvironmentImage& map, int column, int row) {
  const double sin_theta = std::sin(M_PI * (row + 0.5) / map.height);  // the row's centre
  return luminance(&map.rgb[(std::size_t(row) * map.width + column) * 3]) * sin_theta;
}

double environment_integral(const EnvironmentImage& map) {
  double sum = 0.0;
  for (int row = 0; row < map.height; ++row) {
    // a texel of the row spans the solid angle 2 pi (cos theta_top - cos theta_bottom) / W
    const double solid_angle =
        2.0 * M_PI * (std::cos(M_PI * row / map.height) - std::cos(M_PI * (row + 1) / map.height)) / map.width;
    for (int column = 0; column < map.width; ++column) {
      const float* rgb = &map.rgb[(std::size_t(row) * map.width + column) * 3];
      sum += (double(rgb[0]) + rgb[1] + rgb[2]) / 3.0 * solid_angle;
    }
  }
  return sum;
}

std::vector<float> pack_environment(const EnvironmentImage& map) {
  std::vector<float> out;
  if (map.empty()) return out;
  const auto width = std::uint32_t(map.width), height = std::uint32_t(map.height);
  out.reserve(environment_packed_floats(width, height));
  std::vector<double> row_weights(height, 0.0), weights(width);
  for (int row = 0; row < map.height; ++row)
    for (int column = 0; column < map.width; ++column) row_weights[row] += environment_sampling_weight(map, column, row);
  append_cdf(row_weights, out);  // the marginal over rows
  for (int row = 0; row < map.height; ++row) {
    for (int column = 0; column < map.width; ++column) weights[column] = environment_sampling_weight(map, column, row);
    append_cdf(weights, out);  // the conditional over the row's columns
  }
  out.insert(out.end(), map.rgb.begin(), map.rgb.end());
  return out;
}

}  // namespace bp

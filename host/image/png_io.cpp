// Tone-mapped 8-bit sRGB PNG through stb_image_write, written atomically.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include "image/atomic_file.h"
#include "image/image.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace bp {

float srgb_encode(float linear) {
  // IEC 61966-2-1: linear segment below 0.0031308, then 1.055 v^(1/2.4) - 0.055.
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

void write_png(const std::string& path, const ImageRGB& image, float exposure_stops) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != std::size_t(image.width) * image.height * 3)
    throw std::runtime_error("cannot write PNG '" + path + "': image is empty or malformed");
  const float scale = std::exp2(exposure_stops);
  std::vector<std::uint8_t> bytes(image.rgb.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    float v = image.rgb[i] * scale;
    v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
    bytes[i] = static_cast<std::uint8_t>(std::lround(srgb_encode(v) * 255.0f));
  }
  std::vector<unsigned char> encoded;
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &encoded, image.width, image.height, 3, bytes.data(), image.width * 3))
    throw std::runtime_error("cannot write PNG '" + path + "': encoding failed");

  write_file_atomically(path, "PNG", [&](const std::string& temporary) {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw std::runtime_error("cannot create '" + temporary + "': " + std::strerror(errno));
    stream.write(reinterpret_cast<const char*>(encoded.data()), std::streamsize(encoded.size()));
    stream.close();
    if (stream.fail()) throw std::runtime_error("error writing '" + temporary + "'");
  });
}

}  // namespace bp

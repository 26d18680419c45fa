// float32 OpenEXR with named RGB layers (docs/design.md §7): "" is R,G,B; layer L is L.R, L.G, L.B.
#include "image/atomic_file.h"
#include "image/image.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <stdexcept>

namespace bp {
namespace {

constexpr const char* kChannels[3] = {"R", "G", "B"};

std::string channel_name(const std::string& layer, int c) {
  return layer.empty() ? std::string(kChannels[c]) : layer + "." + kChannels[c];
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "'" : ", '") + n + "'";
  return out.empty() ? "none" : out;
}

// Layers of a channel list that have all of R, G and B; "" (the main image) first.
std::vector<std::string> rgb_layers(const Imf::ChannelList& channels) {
  std::vector<std::string> layers;
  for (auto it = channels.begin(); it != channels.end(); ++it) {
    const std::string name = it.name();
    std::string layer;
    if (name == "R") layer = "";
    else if (name.size() > 2 && name.compare(name.size() - 2, 2, ".R") == 0)
      layer = name.substr(0, name.size() - 2);
    else continue;
    if (channels.findChannel(channel_name(layer, 1)) && channels.findChannel(channel_name(layer, 2))) {
      if (layer.empty()) layers.insert(layers.begin(), layer);
      else layers.push_back(layer);
    }
  }
  return layers;
}

}  // namespace

void write_exr(const std::string& path, const std::vector<ImageLayer>& layers) {
  if (layers.empty()) throw std::runtime_error("cannot write EXR '" + path + "': no layers given");
  std::set<std::string> seen;
  for (const auto& layer : layers) {
    if (!layer.image)
      throw std::runtime_error("cannot write EXR '" + path + "': layer '" + layer.name + "' has no image");
    if (!seen.insert(layer.name).second)
      throw std::runtime_error("cannot write EXR '" + path + "': layer '" + layer.name + "' given twice");
    const ImageRGB& first = *layers.front().image;
    if (layer.image->width != first.width || layer.image->height != first.height)
      throw std::runtime_error("cannot write EXR '" + path + "': layer '" + layer.name + "' is " +
                               std::to_string(layer.image->width) + "x" + std::to_string(layer.image->height) +
                               ", layer '" + layers.front().name + "' is " + std::to_string(first.width) +
                               "x" + std::to_string(first.height));
    if (layer.image->width <= 0 || layer.image->height <= 0)
      throw std::runtime_error("cannot write EXR '" + path + "': empty image");
  }
  const int width = layers.front().image->width, height = layers.front().image->height;

  write_file_atomically(path, "EXR", [&](const std::string& temporary) {
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame;
    const std::size_t x_stride = 3 * sizeof(float), y_stride = x_stride * std::size_t(width);
    for (const auto& layer : layers) {
      for (int c = 0; c < 3; ++c) {
        const std::string name = channel_name(layer.name, c);
        header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        // OpenEXR's Slice takes a non-const pointer, but only reads through it when writing.
        char* base = reinterpret_cast<char*>(const_cast<float*>(layer.image->rgb.data() + c));
        frame.insert(name, Imf::Slice(Imf::FLOAT, base, x_stride, y_stride));
      }
    }
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw std::runtime_error("cannot create '" + temporary + "': " + std::strerror(errno));
    {
      Imf::StdOFStream exr_stream(stream, temporary.c_str());
      Imf::OutputFile file(exr_stream, header);
      file.setFrameBuffer(frame);
      file.writePixels(height);
    }  // the destructor writes the line-offset table
    stream.close();
    if (stream.fail()) throw std::runtime_error("error writing '" + temporary + "'");
  });
}

ImageRGB read_exr(const std::string& path, const std::string& layer) {
  try {
    Imf::InputFile file(path.c_str());
    const Imf::ChannelList& channels = file.header().channels();
    for (int c = 0; c < 3; ++c)
      if (!channels.findChannel(channel_name(layer, c)))
        throw std::runtime_error("no layer '" + layer + "' (channel " + channel_name(layer, c) +
                                 " missing; RGB layers: " + quoted_list(rgb_layers(channels)) + ")");
    const Imath::Box2i window = file.header().dataWindow();
    ImageRGB image(window.max.x - window.min.x + 1, window.max.y - window.min.y + 1);
    Imf::FrameBuffer frame;
    for (int c = 0; c < 3; ++c)
      frame.insert(channel_name(layer, c),
                   Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, window, 3 * sizeof(float),
                                    3 * sizeof(float) * std::size_t(image.width)));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read layer '" + layer + "' of EXR '" + path + "': " + e.what());
  }
}

std::vector<std::string> exr_layer_names(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    return rgb_layers(file.header().channels());
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read EXR '" + path + "': " + e.what());
  }
}

}  // namespace bp

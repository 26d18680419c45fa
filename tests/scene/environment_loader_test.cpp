// --environment FILE.exr (host/scene/environment_map.h): what is read, and one-line errors naming
// the file for everything that cannot be a radiance map. The EXR files are written here, not committed.
#include "e2e/cli_runner.h"
#include "image/image.h"
#include "scene/environment_map.h"
#include "scene/gltf_loader.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <gtest/gtest.h>
#include <cmath>
#include <fstream>

namespace bp::test {
namespace {

ImageRGB constant_image(int width, int height, float value) {
  ImageRGB image(width, height);
  std::fill(image.rgb.begin(), image.rgb.end(), value);
  return image;
}

// The SceneError's message, "" if it loads.
std::string load_error(const std::string& path) {
  try {
    load_environment_exr(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(EnvironmentLoader, ReadsRgbTopRowFirst) {
  const std::string path = fresh_dir("env_loader") + "/map.exr";
  ImageRGB image(4, 2);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = float(i);
  write_exr(path, {{"", &image}});
  const EnvironmentImage map = load_environment_exr(path);
  ASSERT_EQ(map.width, 4);
  ASSERT_EQ(map.height, 2);
  EXPECT_EQ(map.rgb, image.rgb);
}

TEST(EnvironmentLoader, BadFilesAreOneLineErrorsNamingTheFile) {
  const std::string dir = fresh_dir("env_loader_bad");
  struct Case { std::string file, needle; };
  std::vector<Case> cases = {{dir + "/missing.exr", "no such file"},
                             {dir + "/text.exr", "not an OpenEXR file"},
                             {dir + "/truncated.exr", "cannot read"},
                             {dir + "/no-rgb.exr", "cannot read"},
                             {dir + "/wide.exr", "beyond the limit"},
                             {dir + "/nan.exr", "finite and >= 0"},
                             {dir + "/negative.exr", "finite and >= 0"}};
  std::ofstream(dir + "/text.exr") << "not an image\n";
  {  // the magic number, then nothing: no header to read (OpenEXR writes no 0 x 0 image to test "empty" with)
    std::ofstream out(dir + "/truncated.exr", std::ios::binary);
    out.write("\x76\x2f\x31\x01\x02\x00", 6);
  }
  {  // a luminance channel only
    Imf::Header header(2, 2);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    std::vector<float> y(4, 1.0f);
    Imf::FrameBuffer frame;
    frame.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), sizeof(float), 2 * sizeof(float)));
    Imf::OutputFile file((dir + "/no-rgb.exr").c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(2);
  }
  const ImageRGB wide = constant_image(kEnvironmentMaxWidth + 1, 1, 1.0f);
  write_exr(dir + "/wide.exr", {{"", &wide}});
  ImageRGB nan = constant_image(4, 2, 1.0f), negative = nan;
  nan.rgb[5] = NAN;
  negative.rgb[7] = -0.5f;
  write_exr(dir + "/nan.exr", {{"", &nan}});
  write_exr(dir + "/negative.exr", {{"", &negative}});
  for (const Case& c : cases) {
    const std::string error = load_error(c.file);
    EXPECT_EQ(error.rfind(c.file + ": ", 0), 0u) << c.file << ": " << error;
    EXPECT_NE(error.find(c.needle), std::string::npos) << c.file << ": " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << "one line: " << error;
  }
}

}  // namespace
}  // namespace bp::test

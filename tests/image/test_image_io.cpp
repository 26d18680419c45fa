// EXR/PNG output and the error metrics of host/image (docs/design.md §7).
#include "image/image.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#if __has_include(<stb/stb_image.h>)
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop
#define BP_HAVE_STB_IMAGE 1
#endif

namespace fs = std::filesystem;

namespace {

// A fresh directory per test, removed afterwards.
class ImageIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("bp-image-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::size_t entries() const { return std::distance(fs::directory_iterator(dir_), fs::directory_iterator()); }
  fs::path dir_;
};

bp::ImageRGB pattern(int w, int h, float offset) {
  bp::ImageRGB img(w, h);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = offset + 0.37f * float(i) - 3.0f;
  return img;
}

bool bit_equal(const bp::ImageRGB& a, const bp::ImageRGB& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

}  // namespace

TEST_F(ImageIo, ExrRoundTripIsBitExactForEveryLayer) {
  bp::ImageRGB main_image = pattern(7, 5, 0.25f), pt = pattern(7, 5, 100.0f), rb = pattern(7, 5, -8.0f);
  // Values float16 would ruin: tiny, huge, just above half's maximum, and a non-finite one.
  main_image.pixel(0, 0)[0] = 1e-30f;
  main_image.pixel(1, 0)[1] = 1e30f;
  main_image.pixel(2, 0)[2] = 65505.0f;
  main_image.pixel(6, 4)[0] = 1.0f + std::numeric_limits<float>::epsilon();
  pt.pixel(3, 2)[1] = std::numeric_limits<float>::infinity();
  rb.pixel(0, 4)[2] = std::numeric_limits<float>::denorm_min();
  const std::string path = file("round.exr");
  bp::write_exr(path, {{"", &main_image}, {"pt", &pt}, {"rb", &rb}});

  EXPECT_TRUE(bit_equal(bp::read_exr(path), main_image));
  EXPECT_TRUE(bit_equal(bp::read_exr(path, "pt"), pt));
  EXPECT_TRUE(bit_equal(bp::read_exr(path, "rb"), rb));
  EXPECT_EQ(bp::read_exr(path).pixel(2, 0)[2], 65505.0f);
  EXPECT_EQ(entries(), 1u);  // no temporary left beside it
}

TEST_F(ImageIo, ExrListsLayersMainFirst) {
  bp::ImageRGB a = pattern(3, 2, 0.0f);
  const std::string path = file("layers.exr");
  bp::write_exr(path, {{"rb_raw", &a}, {"", &a}, {"pt", &a}});
  EXPECT_EQ(bp::exr_layer_names(path), (std::vector<std::string>{"", "pt", "rb_raw"}));

  const std::string no_main = file("no_main.exr");
  bp::write_exr(no_main, {{"pt", &a}});
  EXPECT_EQ(bp::exr_layer_names(no_main), (std::vector<std::string>{"pt"}));
  EXPECT_TRUE(bit_equal(bp::read_exr(no_main, "pt"), a));
}

TEST_F(ImageIo, ExrWriteOverwritesAtomically) {
  bp::ImageRGB a = pattern(4, 4, 1.0f), b = pattern(4, 4, 2.0f);
  const std::string path = file("over.exr");
  bp::write_exr(path, {{"", &a}});
  bp::write_exr(path, {{"", &b}});
  EXPECT_TRUE(bit_equal(bp::read_exr(path), b));
  EXPECT_EQ(entries(), 1u);
}

TEST_F(ImageIo, ExrReadErrorsNameFileAndLayer) {
  bp::ImageRGB a = pattern(2, 2, 0.0f);
  const std::string path = file("one.exr");
  bp::write_exr(path, {{"", &a}});
  try {
    bp::read_exr(path, "pt");
    FAIL() << "missing layer did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'pt'"), std::string::npos) << e.what();
  }
  const std::string missing = file("missing.exr");
  try {
    bp::read_exr(missing);
    FAIL() << "missing file did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_THROW(bp::exr_layer_names(missing), std::runtime_error);
  const std::string text = file("not.exr");
  std::ofstream(text) << "this is not an EXR file\n";
  try {
    bp::exr_layer_names(text);
    FAIL() << "non-EXR file did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
  EXPECT_THROW(bp::read_exr(text), std::runtime_error);
}

TEST_F(ImageIo, WriteIntoMissingDirectoryThrowsAndLeavesNothing) {
  bp::ImageRGB a = pattern(2, 2, 0.0f);
  const std::string exr = file("no/such/dir/out.exr"), png = file("no/such/dir/out.png");
  try {
    bp::write_exr(exr, {{"", &a}});
    FAIL() << "write_exr into a missing directory did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(exr), std::string::npos) << e.what();
  }
  try {
    bp::write_png(png, a);
    FAIL() << "write_png into a missing directory did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(png), std::string::npos) << e.what();
  }
  EXPECT_EQ(entries(), 0u);
}

TEST_F(ImageIo, FailedExrWriteKeepsTheOldFileAndNoTemporary) {
  bp::ImageRGB a = pattern(4, 3, 0.0f), wrong = pattern(5, 3, 0.0f);
  const std::string path = file("keep.exr");
  bp::write_exr(path, {{"", &a}});
  EXPECT_THROW(bp::write_exr(path, {{"", &a}, {"pt", &wrong}}), std::runtime_error);  // size mismatch
  EXPECT_THROW(bp::write_exr(path, {}), std::runtime_error);
  // A directory squatting on the temporary name makes the write itself fail.
  fs::create_directory(path + ".tmp-" + std::to_string(::getpid()));
  EXPECT_THROW(bp::write_exr(path, {{"", &wrong}}), std::runtime_error);
  fs::remove(path + ".tmp-" + std::to_string(::getpid()));
  EXPECT_TRUE(bit_equal(bp::read_exr(path), a));
  EXPECT_EQ(entries(), 1u);
}

TEST(Srgb, OetfAtKnownPoints) {
  EXPECT_EQ(bp::srgb_encode(0.0f), 0.0f);
  EXPECT_NEAR(bp::srgb_encode(1.0f), 1.0f, 1e-6);
  EXPECT_NEAR(bp::srgb_encode(0.0031308f), 0.0031308f * 12.92f, 1e-7);   // end of the linear segment
  EXPECT_NEAR(bp::srgb_encode(0.0031309f), 0.0404500f, 1e-5);            // the two pieces meet
  EXPECT_NEAR(bp::srgb_encode(0.001f), 0.01292f, 1e-7);
  EXPECT_NEAR(bp::srgb_encode(0.18f), 0.4613561f, 1e-5);                 // 1.055*0.18^(1/2.4)-0.055
  EXPECT_NEAR(bp::srgb_encode(0.5f), 0.7353570f, 1e-5);
  EXPECT_NEAR(bp::srgb_encode(0.214041f), 0.5f, 1e-5);                   // sRGB 0.5 decoded
}

TEST_F(ImageIo, PngHasTheRightSizeAndValues) {
  bp::ImageRGB img(5, 3);
  img.pixel(0, 0)[0] = 1.0f;                                       // -> 255
  img.pixel(1, 0)[1] = 0.5f;                                       // +1 stop = 1.0 -> 255
  img.pixel(2, 0)[2] = 7.0f;                                       // clamped -> 255
  img.pixel(3, 0)[0] = -1.0f;                                      // clamped -> 0
  img.pixel(4, 0)[0] = std::numeric_limits<float>::quiet_NaN();    // non-finite -> 0
  img.pixel(4, 0)[1] = std::numeric_limits<float>::infinity();     // non-finite -> 0
  img.pixel(0, 2)[0] = 0.09f;                                      // +1 stop = 0.18 -> round(0.46136*255) = 118
  img.pixel(1, 2)[2] = 0.0005f;                                    // +1 stop = 0.001 -> round(0.01292*255) = 3
  const std::string path = file("out.png");
  bp::write_png(path, img, 1.0f);
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EQ(entries(), 1u);
#ifdef BP_HAVE_STB_IMAGE
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 3);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 5);
  EXPECT_EQ(h, 3);
  auto at = [&](int x, int y, int c) { return int(data[(y * w + x) * 3 + c]); };
  EXPECT_EQ(at(0, 0, 0), 255);   // 2.0 after exposure, clamped
  EXPECT_EQ(at(1, 0, 1), 255);
  EXPECT_EQ(at(2, 0, 2), 255);
  EXPECT_EQ(at(3, 0, 0), 0);
  EXPECT_EQ(at(4, 0, 0), 0);
  EXPECT_EQ(at(4, 0, 1), 0);
  EXPECT_EQ(at(0, 2, 0), 118);
  EXPECT_EQ(at(1, 2, 2), 3);
  EXPECT_EQ(at(1, 1, 1), 0);
  stbi_image_free(data);
#else
  GTEST_SKIP() << "stb_image.h not available to read the PNG back";
#endif
}

TEST(Metrics, HandComputedCases) {
  bp::ImageRGB ref(2, 1), img(2, 1);
  // reference: 1 0 0 | 0 0 0 ; image: 2 0 0 | 0 0 0.1
  ref.rgb = {1, 0, 0, 0, 0, 0};
  img.rgb = {2, 0, 0, 0, 0, 0.1f};
  const bp::ErrorMetrics m = bp::compare_images(img, ref);
  // relMSE = (1/(1+0.01) + 0.01/0.01) / 6 ; RMSE = sqrt((1 + 0.01)/6) ; bias = (2.1 - 1)/6
  EXPECT_NEAR(m.rel_mse, (1.0 / 1.01 + double(0.1f) * double(0.1f) / 0.01) / 6.0, 1e-12);
  EXPECT_NEAR(m.rmse, std::sqrt((1.0 + double(0.1f) * double(0.1f)) / 6.0), 1e-12);
  EXPECT_NEAR(m.mean_bias, (2.0 + double(0.1f) - 1.0) / 6.0, 1e-12);

  const bp::ErrorMetrics same = bp::compare_images(ref, ref);
  EXPECT_EQ(same.rel_mse, 0.0);
  EXPECT_EQ(same.rmse, 0.0);
  EXPECT_EQ(same.mean_bias, 0.0);

  // Uniform bias b on a constant reference r: relMSE = b^2/(r^2+0.01), RMSE = |b|, bias = b.
  bp::ImageRGB flat(16, 8), shifted(16, 8);
  std::fill(flat.rgb.begin(), flat.rgb.end(), 0.5f);
  std::fill(shifted.rgb.begin(), shifted.rgb.end(), 0.25f);
  const bp::ErrorMetrics s = bp::compare_images(shifted, flat);
  EXPECT_NEAR(s.rel_mse, 0.0625 / 0.26, 1e-12);
  EXPECT_NEAR(s.rmse, 0.25, 1e-12);
  EXPECT_NEAR(s.mean_bias, -0.25, 1e-12);
}

TEST(Metrics, SizeMismatchNamesBothSizes) {
  bp::ImageRGB a(4, 3), b(3, 4);
  try {
    bp::compare_images(a, b);
    FAIL() << "size mismatch did not throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("4x3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("3x4"), std::string::npos) << e.what();
  }
}

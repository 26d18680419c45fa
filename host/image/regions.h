// An image cut into a grid of regions (docs/design.md §9, "Regional error"): columns x rows blocks, the
// pixel (x, y) in block (x·columns / width, y·rows / height). The regional error estimate and the
// regional RB level (image/rb_level.h) both sum layers over these blocks; bench/regional_error.sh
// and `bundlepath compare --blocks` cut images the same way.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

namespace bp {

// Rec. 709 luminance, the quantity whose block means the regional error is about.
inline double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

struct RegionGrid {
  int columns = 1, rows = 1;  // at most the image's width and height
  int width = 1, height = 1;  // the image's

  // A grid of at most columns x rows over a width x height image (fewer where the image is smaller).
  static RegionGrid over(int width, int height, int columns, int rows);

  std::size_t count() const { return std::size_t(columns) * std::size_t(rows); }
  std::size_t region_of(int x, int y) const {
    return std::size_t(y * rows / height) * std::size_t(columns) + std::size_t(x * columns / width);
  }
  std::vector<std::size_t> pixel_counts() const;
  // Per region and channel (interleaved RGB), the sum of an image's values (interleaved RGB per pixel).
  std::vector<double> sums(const std::vector<double>& rgb) const;
  std::vector<double> sums(const std::vector<float>& rgb) const;
  // Per pixel and channel, values given per region and channel, interpolated bilinearly between the
  // regions' centres (constant beyond the outer centres): a smooth field, no seams at block edges.
  std::vector<double> bilinear(const std::vector<std::array<double, 3>>& per_region) const;
};

}  // namespace bp

#include "image/regions.h"

#include <algorithm>
#include <cmath>

namespace bp {

RegionGrid RegionGrid::over(int width, int height, int columns, int rows) {
  RegionGrid g;
  g.width = std::max(1, width);
  g.height = std::max(1, height);
  g.columns = std::clamp(columns, 1, g.width);
  g.rows = std::clamp(rows, 1, g.height);
  return g;
}

std::vector<std::size_t> RegionGrid::pixel_counts() const {
  std::vector<std::size_t> out(count(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) ++out[region_of(x, y)];
  return out;
}

namespace {
template <class T>
std::vector<double> region_sums(const RegionGrid& g, const std::vector<T>& rgb) {
  std::vector<double> out(g.count() * 3, 0.0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t r = g.region_of(x, y), p = (std::size_t(y) * std::size_t(g.width) + std::size_t(x)) * 3;
      for (std::size_t c = 0; c < 3; ++c) out[r * 3 + c] += double(rgb[p + c]);
    }
  return out;
}

// The two region indices around a pixel centre along one axis, and the second one's weight.
struct Lerp {
  int lo, hi;
  double t;
};
Lerp lerp_at(int pixel, int pixels, int regions) {
  // Region k's centre lies at (k + 0.5) · pixels / regions; the pixel's centre at pixel + 0.5.
  const double u = (double(pixel) + 0.5) * double(regions) / double(pixels) - 0.5;
  if (u <= 0.0) return {0, 0, 0.0};
  if (u >= double(regions - 1)) return {regions - 1, regions - 1, 0.0};
  const int lo = int(std::floor(u));
  return {lo, lo + 1, u - double(lo)};
}
}  // namespace

std::vector<double> RegionGrid::sums(const std::vector<double>& rgb) const { return region_sums(*this, rgb); }
std::vector<double> RegionGrid::sums(const std::vector<float>& rgb) const { return region_sums(*this, rgb); }

std::vector<double> RegionGrid::bilinear(const std::vector<std::array<double, 3>>& per_region) const {
  std::vector<double> out(std::size_t(width) * std::size_t(height) * 3);
  std::vector<Lerp> along_x(std::size_t(width), Lerp{0, 0, 0.0});
  for (int x = 0; x < width; ++x) along_x[std::size_t(x)] = lerp_at(x, width, columns);
  for (int y = 0; y < height; ++y) {
    const Lerp ly = lerp_at(y, height, rows);
    for (int x = 0; x < width; ++x) {
      const Lerp lx = along_x[std::size_t(x)];
      const auto at = [&](int row, int column) -> const std::array<double, 3>& {
        return per_region[std::size_t(row) * std::size_t(columns) + std::size_t(column)];
      };
      const std::size_t p = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
      for (std::size_t c = 0; c < 3; ++c) {
        const double top = (1.0 - lx.t) * at(ly.lo, lx.lo)[c] + lx.t * at(ly.lo, lx.hi)[c];
        const double bottom = (1.0 - lx.t) * at(ly.hi, lx.lo)[c] + lx.t * at(ly.hi, lx.hi)[c];
        out[p + c] = (1.0 - ly.t) * top + ly.t * bottom;
      }
    }
  }
  return out;
}

}  // namespace bp

#include "image/share_correction.h"

#include "image/regions.h"

#include <algorithm>
#include <cmath>

namespace bp {
namespace {

// Per block of `grid`, the mean over the block and its eight neighbours (clamped at the border) of
// `per_block` (one value per block).
std::vector<double> pooled(const RegionGrid& grid, const std::vector<double>& per_block) {
  std::vector<double> out(per_block.size(), 0.0);
  for (int by = 0; by < grid.rows; ++by)
    for (int bx = 0; bx < grid.columns; ++bx) {
      double sum = 0.0;
      int n = 0;
      for (int y = std::max(0, by - 1); y <= std::min(grid.rows - 1, by + 1); ++y)
        for (int x = std::max(0, bx - 1); x <= std::min(grid.columns - 1, bx + 1); ++x) {
          sum += per_block[std::size_t(y) * std::size_t(grid.columns) + std::size_t(x)];
          ++n;
        }
      out[std::size_t(by) * std::size_t(grid.columns) + std::size_t(bx)] = sum / double(n);
    }
  return out;
}

}  // namespace

ShareCorrection correct_share(const ImageRGB& rb, const ImageRGB& d, const std::vector<double>& d_variance) {
  const int width = rb.width, height = rb.height;
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  ShareCorrection out{rb, std::vector<double>(pixels, 0.0), std::vector<double>(pixels * 3, 0.0)};
  if (d_variance.size() != pixels * 3 || d.rgb.size() != rb.rgb.size()) return out;
  for (double v : d_variance)
    if (!std::isfinite(v)) return out;
  std::vector<double> share(out.share.rgb.begin(), out.share.rgb.end());
  std::vector<double> block_lambda;  // per pixel, the last block level's λ: the pixel level's gate
  const std::vector<double> d_values(d.rgb.begin(), d.rgb.end());
  for (int edge : kShareCorrectionBlocks) {
    const RegionGrid grid =
        RegionGrid::over(width, height, (width + edge - 1) / edge, (height + edge - 1) / edge);
    const std::size_t blocks = grid.count();
    const std::vector<std::size_t> counts = grid.pixel_counts();
    const std::vector<double> d_sums = grid.sums(d_values), share_sums = grid.sums(share),
                              variance_sums = grid.sums(d_variance);
    // Per block and channel the residual of the means, and per block (luminance) its square and V_d.
    std::vector<std::array<double, 3>> residual(blocks);
    std::vector<double> residual_sq(blocks), v_d(blocks), residual_sq_channel[3], v_d_channel[3];
    for (int c = 0; c < 3; ++c) residual_sq_channel[c].resize(blocks), v_d_channel[c].resize(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
      const double n = double(counts[b]);
      for (int c = 0; c < 3; ++c) {
        residual[b][std::size_t(c)] = (d_sums[b * 3 + c] - share_sums[b * 3 + c]) / n;
        residual_sq_channel[c][b] = residual[b][std::size_t(c)] * residual[b][std::size_t(c)];
        v_d_channel[c][b] = variance_sums[b * 3 + c] / (n * n);
      }
      const double e = luminance(residual[b][0], residual[b][1], residual[b][2]);
      residual_sq[b] = e * e;
      // The luminance's variance, the channels taken as independent (an upper bound for PT's
      // positively correlated channels, so λ errs towards RB's share).
      v_d[b] = (0.2126 * 0.2126 * variance_sums[b * 3] + 0.7152 * 0.7152 * variance_sums[b * 3 + 1] +
                0.0722 * 0.0722 * variance_sums[b * 3 + 2]) / (n * n);
    }
    const std::vector<double> e2 = pooled(grid, residual_sq), v = pooled(grid, v_d);
    std::vector<double> lambda(blocks);
    for (std::size_t b = 0; b < blocks; ++b)
      lambda[b] = e2[b] > 0.0 ? std::clamp(1.0 - kShareCorrectionThreshold * v[b] / e2[b], 0.0, 1.0) : 0.0;
    if (edge == 1) {  // the pixel level: no field, and what it leaves is the share's error
      std::vector<double> left[3];
      for (int c = 0; c < 3; ++c) {
        const std::vector<double> e2c = pooled(grid, residual_sq_channel[c]), vc = pooled(grid, v_d_channel[c]);
        left[c].resize(blocks);
        for (std::size_t b = 0; b < blocks; ++b) left[c][b] = e2c[b] - vc[b];
      }
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x), b = grid.region_of(x, y);
          const double l = block_lambda[p] > 0.0 ? lambda[b] : 0.0;  // kShareCorrectionBlocks: the gate
          out.lambda[p] = l;
          for (int c = 0; c < 3; ++c) {
            share[p * 3 + c] += l * residual[b][std::size_t(c)];
            out.left_error[p * 3 + c] = (1.0 - l) * (1.0 - l) * left[c][b];
          }
        }
    } else {
      std::vector<std::array<double, 3>> correction(blocks);
      for (std::size_t b = 0; b < blocks; ++b)
        for (std::size_t c = 0; c < 3; ++c) correction[b][c] = lambda[b] * residual[b][c];
      const std::vector<double> field = grid.bilinear(correction);
      for (std::size_t i = 0; i < share.size(); ++i) share[i] += field[i];
      block_lambda.resize(pixels);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          block_lambda[std::size_t(y) * std::size_t(width) + std::size_t(x)] = lambda[grid.region_of(x, y)];
    }
  }
  for (std::size_t i = 0; i < share.size(); ++i) out.share.rgb[i] = float(share[i]);
  return out;
}

}  // namespace bp

// Running sums of one estimator's per-pixel radiance in double (survives 1e5+ rounds without losing
// precision): its weighted contribution to the combined image, and its unweighted image when kept.
#pragma once
#include "image/image.h"
#include <algorithm>
#include <cstdint>
#include <vector>

namespace bp {

struct Accumulator {
  int width = 0, height = 0;
  std::vector<double> sum;            // interleaved RGB sums of weighted estimates over rounds
  std::vector<double> raw_sum;        // the same unweighted; empty unless kept
  std::uint64_t samples_per_pixel = 0;  // rounds added (PT samples per pixel, or RB iterations)

  Accumulator() = default;
  Accumulator(int w, int h, bool keep_raw = false)
      : width(w), height(h), sum(std::size_t(w) * h * 3, 0.0), raw_sum(keep_raw ? sum.size() : 0, 0.0) {}
  bool keeps_raw() const { return !raw_sum.empty(); }
  // No rounds (a batch's part, before its pass adds into it).
  void clear() {
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(raw_sum.begin(), raw_sum.end(), 0.0);
    samples_per_pixel = 0;
  }
  // Another part's rounds added to these (sized alike).
  void add(const Accumulator& part) {
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += part.sum[i];
    for (std::size_t i = 0; i < raw_sum.size(); ++i) raw_sum[i] += part.raw_sum[i];
    samples_per_pixel += part.samples_per_pixel;
  }
  ImageRGB mean() const { return average(sum); }
  ImageRGB raw_mean() const { return average(raw_sum); }

 private:
  ImageRGB average(const std::vector<double>& s) const {
    ImageRGB img(width, height);
    double inv = samples_per_pixel ? 1.0 / double(samples_per_pixel) : 0.0;
    for (std::size_t i = 0; i < s.size(); ++i) img.rgb[i] = float(s[i] * inv);
    return img;
  }
};

}  // namespace bp

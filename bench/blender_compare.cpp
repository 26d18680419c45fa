// Compares our render of a scene with Cycles' render of the same file (bench/blender_compare.sh):
// the image mean and every BxB-pixel block (default 4x4), and, given a second render of each at
// another seed, the noise floor of those figures at the same sample count.
//
//   blender_compare [--block B] [--png SIDE_BY_SIDE.png] [--exposure STOPS]
//                   OURS.exr CYCLES.exr [OURS_SEED2.exr CYCLES_SEED2.exr]
//
// A block's value is the mean of its pixels' R, G and B; its relative difference is
// (ours - Cycles) / Cycles, both from the first pair (equal spp, the comparison the issue asks for).
// A block where both are 0 differs by 0; where Cycles is 0 and ours is not, by infinity.
// With the second pair: two renders of one renderer differ only by noise, so
//   var(ours - Cycles) = var_ours + var_Cycles = (E(ours1 - ours2)^2 + E(Cycles1 - Cycles2)^2) / 2
// per block; the RMS over blocks of the relative differences ours1 - ours2 and Cycles1 - Cycles2
// gives the RMS that ours1 - Cycles1 would have from noise alone, and what it has beyond that is an
// estimate of a systematic difference. The worst block of ours1 - ours2 and Cycles1 - Cycles2 shows
// how large the worst of the blocks gets from noise alone; ((ours1 - ours2) + (Cycles1 - Cycles2)) / sqrt 2
// is a difference of noise alone with the same variance as ours1 - Cycles1 when neither is biased, so
// its worst block and its count over 5 % are what the comparison would show from noise alone.
// Prints Markdown (for bench/results) and a last line `RESULT mean=... worst_block=... pass=...`.
// Exit 0 whether or not the thresholds (2 % mean, 5 % every block) hold; 2 on bad input.
#include "image/contact_sheet.h"
#include "image/image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr double kMeanThreshold = 0.02;   // the bar: image mean within 2 %
constexpr double kBlockThreshold = 0.05;  // and every 4x4 block within 5 %

double image_mean(const bp::ImageRGB& im) {
  double s = 0.0;
  for (float v : im.rgb) s += v;
  return s / double(im.rgb.size());
}

// Block means (RGB average over the block's pixels), row-major, blocks of the image's full extent
// (a partial last row/column of blocks is left out).
std::vector<double> block_means(const bp::ImageRGB& im, int b, int* bw, int* bh) {
  *bw = im.width / b;
  *bh = im.height / b;
  std::vector<double> out(std::size_t(*bw) * *bh, 0.0);
  for (int by = 0; by < *bh; ++by)
    for (int bx = 0; bx < *bw; ++bx) {
      double s = 0.0;
      for (int y = by * b; y < (by + 1) * b; ++y)
        for (int x = bx * b; x < (bx + 1) * b; ++x) {
          const float* p = im.pixel(x, y);
          s += double(p[0]) + p[1] + p[2];
        }
      out[std::size_t(by) * *bw + bx] = s / (3.0 * b * b);
    }
  return out;
}

double rel(double a, double ref) {
  if (a == ref) return 0.0;
  if (ref == 0.0) return std::numeric_limits<double>::infinity();
  return (a - ref) / ref;
}

struct BlockStats {
  double worst = 0.0;  // largest |relative difference|
  int worst_index = -1;
  double rms = 0.0;     // RMS over blocks of the relative difference
  int over = 0;         // blocks over kBlockThreshold
  int count = 0;
};

// Relative differences of a against b, each block relative to `level` (Cycles' first render).
BlockStats block_stats(const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& level) {
  BlockStats s;
  double sum2 = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = (a[i] == b[i]) ? 0.0 : rel(level[i] + (a[i] - b[i]), level[i]);
    const double m = std::fabs(d);
    if (m > s.worst || s.worst_index < 0) {
      s.worst = m;
      s.worst_index = int(i);
    }
    if (m > kBlockThreshold) ++s.over;
    sum2 += std::isfinite(d) ? d * d : 0.0;
    ++s.count;
  }
  s.rms = std::sqrt(sum2 / std::max(1, s.count));
  return s;
}

void same_size(const bp::ImageRGB& a, const bp::ImageRGB& b, const std::string& what);

// One EXR, or "A.exr+B.exr+...": the mean of those renders (of independent seeds, a render with
// their samples together).
bp::ImageRGB load(const std::string& paths) {
  bp::ImageRGB sum;
  int count = 0;
  for (std::size_t start = 0; start <= paths.size();) {
    const std::size_t plus = std::min(paths.find('+', start), paths.size());
    const bp::ImageRGB image = bp::read_exr(paths.substr(start, plus - start));
    if (count++ == 0) sum = image;
    else {
      same_size(sum, image, paths);
      for (std::size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += image.rgb[i];
    }
    start = plus + 1;
  }
  for (float& v : sum.rgb) v /= float(count);
  return sum;
}

void same_size(const bp::ImageRGB& a, const bp::ImageRGB& b, const std::string& what) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument(what + ": sizes differ (" + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                " and " + std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
}

// The difference panel: per block, red where ours is higher, blue where lower, full at 10 %
// (linear values, so the PNG's sRGB curve makes small differences visible).
bp::ImageRGB difference_panel(const bp::ImageRGB& shape, const std::vector<double>& ours, const std::vector<double>& cyc,
                              int b, int bw) {
  bp::ImageRGB out(shape.width, shape.height);
  for (int y = 0; y < shape.height; ++y)
    for (int x = 0; x < shape.width; ++x) {
      const int bx = x / b, by = y / b;
      if (bx >= bw || by >= int(ours.size()) / bw) continue;
      const std::size_t i = std::size_t(by) * bw + bx;
      const double d = rel(ours[i], cyc[i]);
      const float v = float(std::min(1.0, std::fabs(d) / 0.10));
      float* p = out.pixel(x, y);
      if (d > 0) p[0] = v; else p[2] = v;
    }
  return out;
}

std::string pct(double x, int digits = 2) {
  if (!std::isfinite(x)) return "inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f %%", digits, 100.0 * x);
  return buf;
}

int usage() {
  std::fprintf(stderr,
               "usage: blender_compare [--block B] [--png OUT.png] [--exposure STOPS] [--dump X Y W H] OURS.exr CYCLES.exr "
               "[OURS_SEED2.exr CYCLES_SEED2.exr]\n(each image may be A.exr+B.exr+...: the mean of those renders)\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int block = 4;
  std::string png;
  float exposure = 0.0f;
  int dump[4] = {0, 0, 0, 0};  // --dump X Y W H: print both images' pixels there (RGB mean), ours / Cycles
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--block" && i + 1 < argc) block = std::atoi(argv[++i]);
    else if (a == "--png" && i + 1 < argc) png = argv[++i];
    else if (a == "--exposure" && i + 1 < argc) exposure = float(std::atof(argv[++i]));
    else if (a == "--dump" && i + 4 < argc)
      for (int k = 0; k < 4; ++k) dump[k] = std::atoi(argv[++i]);
    else if (a.rfind("--", 0) == 0) return usage();
    else files.push_back(a);
  }
  if (block < 1 || (files.size() != 2 && files.size() != 4)) return usage();
  try {
    const bp::ImageRGB o1 = load(files[0]), c1 = load(files[1]);
    same_size(o1, c1, files[0] + " and " + files[1]);
    for (int y = dump[1]; y < dump[1] + dump[3] && y < o1.height; ++y) {
      for (int x = dump[0]; x < dump[0] + dump[2] && x < o1.width; ++x) {
        const float *p = o1.pixel(x, y), *q = c1.pixel(x, y);
        std::printf(" %.3f/%.3f", (p[0] + p[1] + p[2]) / 3, (q[0] + q[1] + q[2]) / 3);
      }
      std::printf("   row %d\n", y);
    }
    int bw = 0, bh = 0;
    const auto bo1 = block_means(o1, block, &bw, &bh);
    const auto bc1 = block_means(c1, block, &bw, &bh);
    const double mo = image_mean(o1), mc = image_mean(c1);
    const double mean_rel = rel(mo, mc);
    const BlockStats oc = block_stats(bo1, bc1, bc1);
    std::printf("| image | mean (RGB average) |\n|---|---|\n| ours | %.6g |\n| Cycles | %.6g |\n\n", mo, mc);
    std::printf("Image mean: ours %s from Cycles (bar: 2 %%).\n\n", pct(mean_rel).c_str());
    const int wi = oc.worst_index;
    std::printf("%dx%d blocks: %d (%d x %d). Worst |ours - Cycles| / Cycles: %s, block (%d, %d) from the top left "
                "(Cycles %.4g, ours %.4g); blocks over 5 %%: %d; RMS over blocks: %s.\n\n",
                block, block, oc.count, bw, bh, pct(oc.worst).c_str(), wi % bw, wi / bw, bc1[wi], bo1[wi], oc.over,
                pct(oc.rms).c_str());
    {  // the five worst blocks and how bright they are: relative noise is largest where the image is dark
      std::vector<int> order(bo1.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = int(i);
      auto mag = [&](int i) { return std::fabs(rel(bo1[i], bc1[i])); };
      std::partial_sort(order.begin(), order.begin() + std::min<std::size_t>(5, order.size()), order.end(),
                        [&](int a, int b) { return mag(a) > mag(b); });
      std::printf("The worst blocks (x, y: |difference|, Cycles' level / the image mean):");
      for (std::size_t k = 0; k < std::min<std::size_t>(5, order.size()); ++k)
        std::printf("%s (%d, %d): %s, %.2f", k ? ";" : "", order[k] % bw, order[k] / bw, pct(mag(order[k]), 1).c_str(),
                    bc1[order[k]] / mc);
      std::printf(".\n\n");
    }
    double bias_rms = std::numeric_limits<double>::quiet_NaN(), noise_rms = bias_rms, mean_noise = bias_rms,
           null_worst = bias_rms;
    int null_over = -1;
    if (files.size() == 4) {
      const bp::ImageRGB o2 = load(files[2]), c2 = load(files[3]);
      same_size(o1, o2, files[0] + " and " + files[2]);
      same_size(c1, c2, files[1] + " and " + files[3]);
      const auto bo2 = block_means(o2, block, &bw, &bh);
      const auto bc2 = block_means(c2, block, &bw, &bh);
      const BlockStats oo = block_stats(bo1, bo2, bc1), cc = block_stats(bc1, bc2, bc1);
      // A difference made of noise alone with the variance ours - Cycles has when neither is biased:
      // ((ours1 - ours2) + (Cycles1 - Cycles2)) / sqrt 2, var = (2 var_ours + 2 var_Cycles) / 2.
      std::vector<double> null_a(bo1.size()), zero(bo1.size(), 0.0);
      for (std::size_t i = 0; i < bo1.size(); ++i)
        null_a[i] = ((bo1[i] - bo2[i]) + (bc1[i] - bc2[i])) / std::sqrt(2.0);
      const BlockStats nn = block_stats(null_a, zero, bc1);
      noise_rms = std::sqrt(0.5 * (oo.rms * oo.rms + cc.rms * cc.rms));
      const double excess = oc.rms * oc.rms - noise_rms * noise_rms;
      bias_rms = excess > 0 ? std::sqrt(excess) : 0.0;
      // Noise of the mean difference: the two seeds' means differ by sqrt(2) sigma of one render.
      const double so = std::fabs(image_mean(o2) - mo) / std::sqrt(2.0) / mc;
      const double sc = std::fabs(image_mean(c2) - mc) / std::sqrt(2.0) / mc;
      mean_noise = std::sqrt(so * so + sc * sc);
      std::printf("Noise floor at this sample count, from a second render of each at another seed "
                  "(relative to Cycles' first render, block by block):\n\n");
      std::printf("| pair | worst block | blocks over 5 %% | RMS over blocks | image mean |\n|---|---|---|---|---|\n");
      std::printf("| ours - Cycles (the comparison) | %s | %d | %s | %s |\n", pct(oc.worst).c_str(), oc.over,
                  pct(oc.rms).c_str(), pct(mean_rel).c_str());
      std::printf("| ours seed 1 - ours seed 2 | %s | %d | %s | %s |\n", pct(oo.worst).c_str(), oo.over,
                  pct(oo.rms).c_str(), pct(rel(image_mean(o2), mo) * mo / mc).c_str());
      std::printf("| Cycles seed 1 - Cycles seed 2 | %s | %d | %s | %s |\n", pct(cc.worst).c_str(), cc.over,
                  pct(cc.rms).c_str(), pct(rel(image_mean(c2), mc)).c_str());
      std::printf("| noise alone: ((ours1 - ours2) + (Cycles1 - Cycles2)) / sqrt 2 | %s | %d | %s | |\n\n",
                  pct(nn.worst).c_str(), nn.over, pct(nn.rms).c_str());
      null_worst = nn.worst;
      null_over = nn.over;
      std::printf("From noise alone ours - Cycles would have an RMS over blocks of %s (sqrt of the mean of the "
                  "two squared RMS above); it has %s, so a systematic block difference of about %s RMS "
                  "(0 when within noise). The image mean's noise (1 sigma of ours - Cycles) is about %s.\n\n",
                  pct(noise_rms).c_str(), pct(oc.rms).c_str(), pct(bias_rms).c_str(), pct(mean_noise, 3).c_str());
    }
    if (!png.empty()) {
      const bp::ImageRGB diff = difference_panel(o1, bo1, bc1, block, bw);
      bp::write_contact_sheet(png,
                              {{"ours", &o1},
                               {"Cycles", &c1},
                               {"blocks: red +, blue -, 10 %", &diff}},
                              exposure, 3);
    }
    const bool pass = std::fabs(mean_rel) <= kMeanThreshold && oc.worst <= kBlockThreshold;
    std::printf("RESULT mean=%.6f worst_block=%.6f blocks_over=%d rms_blocks=%.6f noise_rms=%.6f bias_rms=%.6f "
                "mean_noise=%.6f noise_worst_block=%.6f noise_blocks_over=%d pass=%s\n",
                mean_rel, oc.worst, oc.over, oc.rms, noise_rms, bias_rms, mean_noise, null_worst, null_over,
                pass ? "yes" : "no");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "blender_compare: %s\n", e.what());
    return 2;
  }
}

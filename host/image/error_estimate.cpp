#include "image/error_estimate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bp {

std::uint64_t rb_error_batch_iterations(double expected_iterations) {
  if (!std::isfinite(expected_iterations)) return kErrorBatchRbIterations;
  const double blocks = std::floor(std::max(0.0, expected_iterations) / double(kErrorBatchesWanted * kErrorBatchRbBlock));
  return std::uint64_t(std::clamp(blocks * double(kErrorBatchRbBlock), double(kErrorBatchRbBlock),
                                  double(kErrorBatchRbIterations)));
}

BatchMeansErrorEstimate::BatchMeansErrorEstimate(int width, int height, std::uint64_t batch_rounds, int levels,
                                                 std::uint64_t first_round, const RoundSums* start) {
  const std::size_t n = std::size_t(width) * height * 3;
  state_.width = width;
  state_.height = height;
  state_.rounds = first_round;
  if (start) {
    state_.start_sums.resize(n);
    for (std::size_t i = 0; i < n; ++i) state_.start_sums[i] = start->at(i);
  }
  for (int j = 0; j < std::max(1, levels); ++j) {
    Level level;
    level.batch_rounds = std::max<std::uint64_t>(1, batch_rounds) << j;
    level.open_round = first_round;
    level.open_sums = state_.start_sums.empty() ? std::vector<double>(n, 0.0) : state_.start_sums;
    level.sum_sq_over_n.assign(n, 0.0);
    state_.levels.push_back(std::move(level));
  }
}

void BatchMeansErrorEstimate::add(std::uint64_t rounds, const RoundSums& sums) {
  state_.rounds = rounds;
  for (Level& level : state_.levels) {
    const std::uint64_t n = rounds - level.open_round;
    if (n < level.batch_rounds) continue;
    const double inv_n = 1.0 / double(n);
    for (std::size_t i = 0; i < level.open_sums.size(); ++i) {
      const double now = sums.at(i);
      const double batch_sum = now - level.open_sums[i];  // X_k: n_k times the batch mean m_k
      level.sum_sq_over_n[i] += batch_sum * batch_sum * inv_n;  // n_k m_k² (docs/design.md §9)
      level.open_sums[i] = now;
    }
    ++level.batches;
    level.closed_rounds += n;
    level.open_round = rounds;
  }
}

namespace {
// The variance of the image's mean at value i (docs/design.md §9), from a level's closed batches.
struct LevelVariance {
  const BatchMeansErrorEstimate::Level& level;
  const std::vector<double>& start_sums;
  double k, n_closed, n_image;
  double at(std::size_t i) const {
    // Σ X_k over the closed batches: the sums at the open batch's start less those at the first round.
    const double sum = level.open_sums[i] - (start_sums.empty() ? 0.0 : start_sums[i]);
    // Σ n_k (m_k − m)² = Σ X_k²/n_k − (Σ X_k)²/Σ n_k; E = (K − 1) σ² for batches independent (§9).
    const double s2 = std::max(0.0, (level.sum_sq_over_n[i] - sum * sum / n_closed) / (k - 1.0));
    return s2 / n_image;  // Var of the mean of the image's N rounds, σ² / N
  }
};

// The reference value the relMSE divides by at value i (x, y, channel c): the smaller of the pixel
// and the mean of its (up to) 8 neighbours in that channel. A pixel's own noise moves its variance
// estimate and its value together -- a firefly inflates both -- so Var / I² is biased low, most where
// the error is largest; there the neighbours, below the firefly, stand in. Beside a much brighter
// region (a pixel at the light's edge) the neighbours' mean is far above the pixel; there the pixel
// stands. Measured against the same variance over the reference's R² (128x128, seed 9; README,
// "Error estimates"): the pixel alone gives 0.48 of it on cornell-glossy at 16 PT spp and 0.79 on
// cornell-box at 16 spp, the neighbours' mean alone 0.47 on cornell-box combined at c = 1/32, this
// rule 0.81 to 1.03 in every case tried. A 1x1 image has no neighbours: the pixel itself.
template <class PixelValue>
double reference_value(PixelValue image, int width, int height, std::size_t i) {
  const std::size_t c = i % 3, pixel = i / 3;
  const int x = int(pixel % std::size_t(width)), y = int(pixel / std::size_t(width));
  double sum = 0.0;
  int count = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      sum += image((std::size_t(ny) * std::size_t(width) + std::size_t(nx)) * 3 + c);
      ++count;
    }
  return count ? std::min(image(i), sum / count) : image(i);
}

// A variance of the mean already summed per value (ImageErrorEstimate's layers).
struct LevelVarianceOf {
  const std::vector<double>& variance;
  double at(std::size_t i) const { return variance[i]; }
};

template <class Variance, class PixelValue>
double rel_mse_of(const Variance& var, int width, int height, PixelValue image) {
  const std::size_t n = std::size_t(width) * std::size_t(height) * 3;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = reference_value(image, width, height, i);
    sum += var.at(i) / (r * r + 0.01);  // docs/design.md §7's relMSE, E[(I − R)²] = Var, R ≈ reference_value (§9)
  }
  return sum / double(n);
}
}  // namespace

std::vector<double> BatchMeansErrorEstimate::variance_of_mean(int level_index) const {
  const Level& level = state_.levels[std::size_t(level_index)];
  if (level.batches < 2 || state_.rounds == 0) return {};
  const LevelVariance var{level, state_.start_sums, double(level.batches), double(level.closed_rounds),
                          double(state_.rounds)};
  std::vector<double> out(level.open_sums.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = var.at(i);
  return out;
}

double BatchMeansErrorEstimate::estimated_rel_mse(const ImageRGB& image, int level_index) const {
  const Level& level = state_.levels[std::size_t(level_index)];
  if (level.batches < 2 || state_.rounds == 0 || image.rgb.size() != level.open_sums.size()) return std::nan("");
  const LevelVariance var{level, state_.start_sums, double(level.batches), double(level.closed_rounds),
                          double(state_.rounds)};
  return rel_mse_of(var, state_.width, state_.height, [&](std::size_t i) { return double(image.rgb[i]); });
}

double BatchMeansErrorEstimate::estimated_rel_mse(const RoundSums& sums, int level_index) const {
  const Level& level = state_.levels[std::size_t(level_index)];
  if (level.batches < 2 || state_.rounds == 0) return std::nan("");
  const LevelVariance var{level, state_.start_sums, double(level.batches), double(level.closed_rounds),
                          double(state_.rounds)};
  const double inv_rounds = 1.0 / double(state_.rounds);
  return rel_mse_of(var, state_.width, state_.height, [&](std::size_t i) { return sums.at(i) * inv_rounds; });
}

BatchMeansErrorEstimate BatchMeansErrorEstimate::from_state(State state, int width, int height) {
  const std::size_t n = std::size_t(width) * height * 3;
  bool ok = state.width == width && state.height == height && !state.levels.empty() &&
            (state.start_sums.empty() || state.start_sums.size() == n);
  for (const Level& l : state.levels)
    ok = ok && l.open_sums.size() == n && l.sum_sq_over_n.size() == n && l.batch_rounds > 0 &&
         l.open_round <= state.rounds;
  if (!ok)
    throw std::runtime_error("the error estimate's batch statistics do not fit a " + std::to_string(width) + "x" +
                             std::to_string(height) + " image");
  BatchMeansErrorEstimate e;
  e.state_ = std::move(state);
  return e;
}

ImageErrorEstimate::ImageErrorEstimate(int width, int height, std::vector<Layer> layers, int levels,
                                       std::uint64_t first_round,
                                       const std::vector<BatchMeansErrorEstimate::State>* resumed,
                                       std::optional<RoundSums> pt_rb_share)
    : width_(width), height_(height), layers_(std::move(layers)), factors_(layers_.size()), pt_rb_share_(pt_rb_share) {
  const std::size_t states = layers_.size() + (pt_rb_share_ ? 1 : 0);
  if (resumed && resumed->size() != states)
    throw std::runtime_error("the error estimate's batch statistics hold " + std::to_string(resumed->size()) +
                             " layer(s), this render has " + std::to_string(states));
  for (std::size_t l = 0; l < layers_.size(); ++l)
    estimates_.push_back(resumed ? BatchMeansErrorEstimate::from_state((*resumed)[l], width, height)
                                 : BatchMeansErrorEstimate(width, height, layers_[l].batch_rounds, levels, first_round,
                                                           first_round ? &layers_[l].sums : nullptr));
  const std::size_t rb = rb_layer();
  if (pt_rb_share_ && rb < layers_.size())  // d batched with RB's layer: its batches pair with RB's (rb_bias_check)
    pt_rb_share_estimate_.emplace(resumed ? BatchMeansErrorEstimate::from_state(resumed->back(), width, height)
                                          : BatchMeansErrorEstimate(width, height, layers_[rb].batch_rounds, 1,
                                                                    first_round, first_round ? &*pt_rb_share_ : nullptr));
}

std::size_t ImageErrorEstimate::rb_layer() const {
  for (std::size_t l = 0; l < layers_.size(); ++l)
    if (std::string(layers_[l].name) == "rb") return l;
  return layers_.size();
}

void ImageErrorEstimate::add(std::uint64_t rounds) {
  const std::size_t rb = rb_layer();
  if (pt_rb_share_estimate_) {
    const BatchMeansErrorEstimate::Level &r = estimates_[rb].state().levels[0], &d = pt_rb_share_estimate_->state().levels[0];
    // Paired only where d's batches are RB's (a checkpoint of before they were is not).
    const bool paired = d.batch_rounds == r.batch_rounds && d.open_round == r.open_round;
    if (paired && rounds - r.open_round >= r.batch_rounds) add_rb_bias_batch(rb, rounds);
  }
  for (std::size_t l = 0; l < layers_.size(); ++l) estimates_[l].add(rounds, layers_[l].sums);
  if (pt_rb_share_estimate_) pt_rb_share_estimate_->add(rounds, *pt_rb_share_);
}

// RB's batch k closes at `rounds`: E_k = mean over values of y_k·Y_<k / (R̂² + 0.01), y_k = s·r − d
// summed over the batch, Y_<k over the batches before it (from the estimate's start).
void ImageErrorEstimate::add_rb_bias_batch(std::size_t rb, std::uint64_t rounds) {
  const BatchMeansErrorEstimate::State &r = estimates_[rb].state(), &d = pt_rb_share_estimate_->state();
  const BatchMeansErrorEstimate::Level &rl = r.levels[0], &dl = d.levels[0];
  const double n_k = double(rounds - rl.open_round), n_before = double(rl.closed_rounds);
  if (n_before == 0.0) return;  // the first batch has none to pair with
  const double inv_rounds = 1.0 / double(rounds);
  const auto image = [&](std::size_t i) {  // I = Σ layers' sums · factors / rounds, as rel_mse_of
    double sum = 0.0;
    for (std::size_t l = 0; l < layers_.size(); ++l) sum += layers_[l].sums.at(i) * factor(l, i);
    return sum * inv_rounds;
  };
  const std::size_t n = rl.open_sums.size();
  double e = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = factor(rb, i);
    const double r_start = r.start_sums.empty() ? 0.0 : r.start_sums[i], d_start = d.start_sums.empty() ? 0.0 : d.start_sums[i];
    const double y = s * (layers_[rb].sums.at(i) - rl.open_sums[i]) - (pt_rb_share_->at(i) - dl.open_sums[i]);
    const double y_before = s * (rl.open_sums[i] - r_start) - (dl.open_sums[i] - d_start);
    const double ref = reference_value(image, width_, height_, i);
    e += y * y_before / (ref * ref + 0.01);  // E[y_k Y_<k] = n_k N_<k b² (rb_bias_rel_mse), over R̂² + 0.01 as §7
  }
  e /= double(n);
  const double a = n_k * n_before;
  RbBiasSums& t = rb_bias_sums_;
  t.e += e;
  t.e_sq += e * e;
  t.a += a;
  t.a_e += a * e;
  t.a_sq += a * a;
  ++t.batches;
}

namespace {
// The one-sided 95 % quantile of Student's t with `dof` degrees of freedom (kRbBiasFalseAlarm), the
// table's entry at or below dof (so at least the quantile).
double student_t_95(double dof) {
  static constexpr std::array<std::pair<double, double>, 16> kTable{{{1, 6.314}, {2, 2.920}, {3, 2.353}, {4, 2.132},
                                                                     {5, 2.015}, {6, 1.943}, {7, 1.895}, {8, 1.860},
                                                                     {9, 1.833}, {10, 1.812}, {12, 1.782}, {15, 1.753},
                                                                     {20, 1.725}, {30, 1.697}, {60, 1.671}, {120, 1.658}}};
  double q = kTable.front().second;
  for (const auto& [d, quantile] : kTable)
    if (dof >= d) q = quantile;
  return q;
}
static_assert(kRbBiasFalseAlarm == 0.05, "student_t_95's table is the 95 % quantile");
}  // namespace

ImageErrorEstimate::RbBiasCheck ImageErrorEstimate::rb_bias_check() const {
  RbBiasCheck c;
  const RbBiasSums& t = rb_bias_sums_;
  c.batches = t.batches;
  if (t.batches < 2 || !(t.a > 0.0)) return c;
  // The pairs' products average to the bias's relMSE: Σ E_k / Σ a_k.
  c.estimate = t.e / t.a;
  // Without a bias the E_k are a martingale's increments (E[E_k | the batches before] = 0, whatever
  // the pixels' correlation), so Var(Σ E_k) = Σ E[E_k²]; about a bias, their spread about a_k·estimate.
  const double spread = t.e_sq - 2.0 * c.estimate * t.a_e + c.estimate * c.estimate * t.a_sq;
  const double k = double(t.batches);
  c.standard_error = std::sqrt(std::max(0.0, spread) * k / (k - 1.0)) / t.a;
  return c;
}

double ImageErrorEstimate::rb_bias_rel_mse() const {
  if (!pt_rb_share_estimate_) return std::nan("");
  const RbBiasCheck c = rb_bias_check();
  if (std::isnan(c.estimate) || c.batches < kRbBiasMinPairedBatches) return std::nan("");
  return c.estimate > student_t_95(double(c.batches) - 1.0) * c.standard_error ? c.estimate : 0.0;
}

std::uint64_t ImageErrorEstimate::rb_bias_rounds_needed() const {
  if (!pt_rb_share_estimate_) return 0;
  // The check pairs each of RB's closed batches after the first: it counts from batch K + 1 on.
  const BatchMeansErrorEstimate::Level& r = estimates_[rb_layer()].state().levels[0];
  const std::uint64_t batches_needed = kRbBiasMinPairedBatches + 1;
  return r.batches >= batches_needed ? r.open_round : r.open_round + (batches_needed - r.batches) * r.batch_rounds;
}

void ImageErrorEstimate::set_factors(const std::string& layer, std::vector<double> factors) {
  for (std::size_t l = 0; l < layers_.size(); ++l)
    if (layer == layers_[l].name) factors_[l] = std::move(factors);
}

void ImageErrorEstimate::set_rb_regional_level(const RegionGrid& grid, std::vector<double> rb_level_relative_variance,
                                               std::vector<double> corrected_level_relative_variance) {
  rb_level_grid_ = grid;
  rb_level_rho_r_ = std::move(rb_level_relative_variance);
  rb_level_rho_m_ = std::move(corrected_level_relative_variance);
}

std::vector<double> ImageErrorEstimate::layer_variance(std::size_t layer, int level) const {
  std::vector<double> var = estimates_[layer].variance_of_mean(level);
  const bool regional = rb_level_grid_ && std::string(layers_[layer].name) == "rb" && !var.empty();
  const double inv_rounds = estimates_[layer].rounds() ? 1.0 / double(estimates_[layer].rounds()) : 0.0;
  for (std::size_t i = 0; i < var.size(); ++i) {
    const double f = factor(layer, i);
    if (regional) {
      const std::size_t pixel = i / 3;
      const std::size_t b = rb_level_grid_->region_of(int(pixel % std::size_t(width_)), int(pixel / std::size_t(width_)));
      const double rho_r = rb_level_rho_r_[b], rho_m = rb_level_rho_m_[b];
      if (std::isfinite(rho_r) && std::isfinite(rho_m)) {
        const double r = layers_[layer].sums.at(i) * inv_rounds;
        // Var(s·r) = s² max(0, Var(r) − r² ρ_r) + (s·r)² ρ_M   (set_rb_regional_level)
        var[i] = f * f * std::max(0.0, var[i] - r * r * rho_r) + f * f * r * r * rho_m;
        continue;
      }
    }
    var[i] *= f * f;  // Var(f·X) = f² Var(X)
  }
  return var;
}

void ImageErrorEstimate::set_consistent_share(std::vector<double> mean_square_error, std::vector<float> image) {
  consistent_mse_ = std::move(mean_square_error);
  consistent_image_ = std::move(image);
}

std::vector<double> ImageErrorEstimate::variance_of_mean(int level) const {
  if (level == 0 && !consistent_mse_.empty()) return consistent_mse_;
  std::vector<double> sum;
  for (std::size_t l = 0; l < estimates_.size(); ++l) {
    std::vector<double> var = layer_variance(l, level);
    if (var.empty()) return {};
    if (sum.empty()) sum = std::move(var);
    else
      for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += var[i];  // independent layers: Var(Σ) = Σ Var
  }
  return sum;
}

double ImageErrorEstimate::rel_mse_of(const std::vector<double>& variance) const {
  if (variance.empty() || estimates_.empty() || estimates_.front().rounds() == 0) return std::nan("");
  const double inv_rounds = 1.0 / double(estimates_.front().rounds());
  const LevelVarianceOf var{variance};
  return bp::rel_mse_of(var, width_, height_, [&](std::size_t i) {
    if (!consistent_image_.empty()) return double(consistent_image_[i]);
    double image = 0.0;  // I = Σ layers' sums · factors / rounds
    for (std::size_t l = 0; l < layers_.size(); ++l) image += layers_[l].sums.at(i) * factor(l, i);
    return image * inv_rounds;
  });
}

double ImageErrorEstimate::estimated_rel_mse(int level) const {
  const double variance = rel_mse_of(variance_of_mean(level)), bias = rb_bias_rel_mse();
  // Under --rb-level consistent the mean square error holds RB's bias already.
  return std::isnan(bias) || (level == 0 && !consistent_mse_.empty()) ? variance : variance + bias;
}

double ImageErrorEstimate::layer_rel_mse(std::size_t layer, int level) const {
  return rel_mse_of(layer_variance(layer, level));
}

double ImageErrorEstimate::degrees_of_freedom() const {
  double sum = 0.0, sum_sq_over_dof = 0.0;
  for (std::size_t l = 0; l < estimates_.size(); ++l) {
    const double v = layer_rel_mse(l), dof = double(estimates_[l].batches()) - 1.0;
    if (!(dof >= 1.0) || !std::isfinite(v)) return 0.0;
    sum += v;
    sum_sq_over_dof += v * v / dof;  // Welch–Satterthwaite: ν = (Σ V_l)² / Σ (V_l² / ν_l)
  }
  if (estimates_.empty()) return 0.0;
  if (sum_sq_over_dof <= 0.0) {  // no variance at all: the least of the layers' freedoms
    double least = INFINITY;
    for (const BatchMeansErrorEstimate& e : estimates_) least = std::min(least, double(e.batches()) - 1.0);
    return least;
  }
  return sum * sum / sum_sq_over_dof;
}

ImageRGB ImageErrorEstimate::standard_error() const {
  ImageRGB out(width_, height_);
  const std::vector<double> var = variance_of_mean(0);
  for (std::size_t i = 0; i < var.size(); ++i) out.rgb[i] = float(std::sqrt(std::max(0.0, var[i])));
  return out;
}

std::vector<BatchMeansErrorEstimate::State> ImageErrorEstimate::state() const {
  std::vector<BatchMeansErrorEstimate::State> out;
  for (const BatchMeansErrorEstimate& e : estimates_) out.push_back(e.state());
  if (pt_rb_share_estimate_) out.push_back(pt_rb_share_estimate_->state());
  return out;
}

}  // namespace bp

#include "image/regional_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bp {

int RegionalError::packed_width(const Track& t) const {
  const std::size_t n = t.per_pixel ? std::size_t(grid_.width) * std::size_t(grid_.height) : grid_.count();
  return int((n + 2) / 3);
}

RegionalError::RegionalError(RegionGrid grid, const Inputs& in, std::uint64_t first_round,
                             const std::optional<State>& resumed)
    : grid_(grid), in_(in) {
  for (std::size_t n : grid_.pixel_counts()) inv_pixels_.push_back(1.0 / double(n));
  const auto make = [&](std::optional<Track>& t, bool per_pixel) {
    t.emplace();
    t->per_pixel = per_pixel;
    t->sums.assign(std::size_t(packed_width(*t)) * 3, 0.0);
  };
  if (in_.pt) make(w_, true);
  if (in_.pt && in_.pt->keeps_raw()) make(u_, true);
  if (in_.rb) make(r_, false);
  if (u_ && r_) make(d_, true);
  update_sums();
  std::size_t k = 0;
  for (Track* t : tracks()) {
    t->round_sums = RoundSums{&t->sums, 1.0};
    const std::uint64_t batch_rounds = t->per_pixel ? 1 : in_.rb_batch_rounds;
    if (!resumed) {
      t->estimate.emplace(packed_width(*t), 1, batch_rounds, 1, first_round, first_round ? &t->round_sums : nullptr);
    } else {
      if (k >= resumed->layers.size())
        throw std::runtime_error("the regional error's batch statistics hold fewer layers than this render");
      t->estimate.emplace(BatchMeansErrorEstimate::from_state(resumed->layers[k], packed_width(*t), 1));
    }
    ++k;
  }
  if (resumed && k != resumed->layers.size())
    throw std::runtime_error("the regional error's batch statistics hold more layers than this render");
  rb_factors_.assign(grid_.count(), 1.0);
  if (r_) rb_batches_seen_ = r_->estimate->batches();
}

std::vector<RegionalError::Track*> RegionalError::tracks() {
  std::vector<Track*> out;
  for (std::optional<Track>* t : {&w_, &u_, &r_, &d_})
    if (*t) out.push_back(&**t);
  return out;
}
std::vector<const RegionalError::Track*> RegionalError::tracks() const {
  std::vector<const Track*> out;
  for (const std::optional<Track>* t : {&w_, &u_, &r_, &d_})
    if (*t) out.push_back(&**t);
  return out;
}

void RegionalError::update_sums() {
  // Per pixel (PT's tracks) or region (RB's), the luminance of a round's estimate summed over rounds:
  // a region's mean is Σ over its pixels / its pixels / rounds.
  const std::size_t pixels = std::size_t(grid_.width) * std::size_t(grid_.height);
  const auto per_pixel = [&](Track& t, const std::vector<double>& rgb, const std::vector<double>* minus, double per_round) {
    for (std::size_t p = 0; p < pixels; ++p) {
      double y = luminance(rgb[p * 3], rgb[p * 3 + 1], rgb[p * 3 + 2]);
      if (minus) y -= luminance((*minus)[p * 3], (*minus)[p * 3 + 1], (*minus)[p * 3 + 2]);
      t.sums[p] = y * per_round;
    }
  };
  if (w_) per_pixel(*w_, in_.pt->sum, nullptr, 1.0 / in_.pt_samples);
  if (u_) per_pixel(*u_, in_.pt->raw_sum, nullptr, 1.0 / in_.pt_samples);
  if (d_) per_pixel(*d_, in_.pt->raw_sum, &in_.pt->sum, 1.0 / in_.pt_samples);  // d = u − w
  if (r_) {
    const std::vector<double> region_rgb = grid_.sums(in_.rb->sum);
    for (std::size_t r = 0; r < grid_.count(); ++r)
      r_->sums[r] = luminance(region_rgb[r * 3], region_rgb[r * 3 + 1], region_rgb[r * 3 + 2]) / in_.rb_iterations *
                    inv_pixels_[r];
  }
}

void RegionalError::add(std::uint64_t rounds) {
  const std::vector<double> rb_before = r_ ? r_->estimate->state().levels[0].open_sums : std::vector<double>{};
  const std::uint64_t rb_open_round = r_ ? r_->estimate->state().levels[0].open_round : 0;
  update_sums();
  for (Track* t : tracks()) t->estimate->add(rounds, t->round_sums);
  if (r_ && r_->estimate->batches() > rb_batches_seen_) {  // a batch of RB closed: keep its region means
    rb_batches_seen_ = r_->estimate->batches();
    const double n = double(rounds - rb_open_round);
    for (std::size_t b = 0; b < grid_.count(); ++b) r_->batch_means.push_back((r_->sums[b] - rb_before[b]) / n);
  }
}

void RegionalError::set_rb_factors(std::vector<double> pixel_factors, bool regional_field) {
  regional_field_ = regional_field;
  rb_factors_.assign(grid_.count(), 1.0);
  if (pixel_factors.empty() || !in_.rb) return;
  // s_b: the factors' effect on the region's mean luminance of RB's layer, Y(Σ f·rb) / Y(Σ rb).
  std::vector<double> scaled(in_.rb->sum.size());
  for (std::size_t i = 0; i < scaled.size(); ++i) scaled[i] = in_.rb->sum[i] * pixel_factors[i];
  const std::vector<double> with = grid_.sums(scaled), without = grid_.sums(in_.rb->sum);
  for (std::size_t b = 0; b < grid_.count(); ++b) {
    const double y = luminance(without[b * 3], without[b * 3 + 1], without[b * 3 + 2]);
    if (y > 0.0) rb_factors_[b] = luminance(with[b * 3], with[b * 3 + 1], with[b * 3 + 2]) / y;
  }
}

// Per region, the sum over its pixels (per_pixel tracks) or the region's value, over the region's
// pixels for a pixel track: values given per track slot.
std::vector<double> RegionalError::region_totals(const Track& t, const std::vector<double>& values, bool squared_scale) const {
  std::vector<double> out(grid_.count(), 0.0);
  if (!t.per_pixel) {
    for (std::size_t b = 0; b < out.size(); ++b) out[b] = values[b];
    return out;
  }
  for (int y = 0; y < grid_.height; ++y)
    for (int x = 0; x < grid_.width; ++x)
      out[grid_.region_of(x, y)] += values[std::size_t(y) * std::size_t(grid_.width) + std::size_t(x)];
  for (std::size_t b = 0; b < out.size(); ++b) out[b] *= squared_scale ? inv_pixels_[b] * inv_pixels_[b] : inv_pixels_[b];
  return out;
}

std::vector<double> RegionalError::means(const Track& t) const {
  const std::uint64_t rounds = t.estimate->rounds();
  if (rounds == 0) return std::vector<double>(grid_.count(), std::nan(""));
  std::vector<double> out = region_totals(t, t.sums, false);
  for (double& v : out) v /= double(rounds);
  return out;
}

// A region's variance of its mean: RB's from its batch means; PT's, its independent pixels'
// variances summed, Σ Var(Y_p) / n².
std::vector<double> RegionalError::variances(const Track& t) const {
  const std::vector<double> var = t.estimate->variance_of_mean();
  if (var.empty()) return std::vector<double>(grid_.count(), std::nan(""));
  return region_totals(t, var, true);
}

std::vector<double> RegionalError::rb_variances() const {
  std::vector<double> v = variances(*r_);
  const std::vector<double> r = means(*r_);
  const double own_dof = double(r_->estimate->batches()) - 1.0;
  double pooled_variance = 0.0, pooled_square = 0.0;  // q̄ = Σ V_r / Σ r²
  for (std::size_t b = 0; b < v.size(); ++b)
    if (std::isfinite(v[b] + r[b])) {
      pooled_variance += v[b];
      pooled_square += r[b] * r[b];
    }
  if (!(own_dof >= 1.0) || !(pooled_square > 0.0)) return v;
  const double pooled_relative = pooled_variance / pooled_square, prior_dof = kRegionalRbPoolDegreesOfFreedom;
  // (ν V_r + ν₀ q̄ r²) / (ν + ν₀): the region's own variance and the pool's at its level
  for (std::size_t b = 0; b < v.size(); ++b)
    if (std::isfinite(v[b] + r[b])) v[b] = (own_dof * v[b] + prior_dof * pooled_relative * r[b] * r[b]) / (own_dof + prior_dof);
  return v;
}

namespace {
// RB's discretisation bias in a region, squared, as far as PT sees it: r and d estimate the same
// share, d without bias, so E[(r − d)²] = b² + V_r + V_d; the estimate max(0, (r − d)² − V_r − V_d).
double rb_bias_squared(double v_r, double v_d, double r, double d) { return std::max(0.0, (r - d) * (r - d) - v_r - v_d); }
// RB's weight λ in its region's share, λ r + (1 − λ) d: the least mean squared error with r biased by
// b, λ = V_d / (V_r + V_d + b²); the inverse-variance weight where r and d agree within their noise.
double rb_weight(double v_r, double v_d, double bias_squared) {
  const double total = v_r + v_d + bias_squared;
  return total > 0.0 ? v_d / total : 1.0;
}
// Both, for a region's variances and means of r and d.
struct RbShareMix {
  double bias_squared, lambda;
};
RbShareMix rb_share_mix(double v_r, double v_d, double r, double d) {
  const double bias_squared = rb_bias_squared(v_r, v_d, r, d);
  return RbShareMix{bias_squared, rb_weight(v_r, v_d, bias_squared)};
}
}  // namespace

std::vector<double> RegionalError::rb_weights() const {
  std::vector<double> out(grid_.count(), std::nan(""));
  if (!r_ || !d_) return out;
  const std::vector<double> v_r = rb_variances(), v_d = variances(*d_), r = means(*r_), d = means(*d_);
  for (std::size_t b = 0; b < out.size(); ++b)
    if (!std::isnan(v_r[b] + v_d[b] + r[b] + d[b])) out[b] = rb_share_mix(v_r[b], v_d[b], r[b], d[b]).lambda;
  return out;
}

RegionalError::RbLevelVariances RegionalError::rb_level_relative_variances() const {
  RbLevelVariances out{std::vector<double>(grid_.count(), std::nan("")), std::vector<double>(grid_.count(), std::nan(""))};
  if (!r_ || !d_) return out;
  const std::vector<double> v_r = rb_variances(), v_d = variances(*d_), r = means(*r_), d = means(*d_);
  for (std::size_t b = 0; b < grid_.count(); ++b) {
    if (std::isnan(v_r[b] + v_d[b]) || !(r[b] > 0.0)) continue;
    const RbShareMix mix = rb_share_mix(v_r[b], v_d[b], r[b], d[b]);
    const double lambda = mix.lambda, level = lambda * r[b] + (1.0 - lambda) * d[b];
    if (!(level > 0.0)) continue;
    out.rb[b] = v_r[b] / (r[b] * r[b]);
    // Var(λ r + (1 − λ) d) with RB's bias counted, over the level squared
    out.corrected[b] = (lambda * lambda * (v_r[b] + mix.bias_squared) + (1.0 - lambda) * (1.0 - lambda) * v_d[b]) / (level * level);
  }
  return out;
}

std::vector<double> RegionalError::region_means() const {
  const std::size_t n = grid_.count();
  const std::vector<double> none(n, 0.0);
  const std::vector<double> w = w_ ? means(*w_) : none, r = r_ ? means(*r_) : none;
  std::vector<double> out(n);
  for (std::size_t b = 0; b < n; ++b) out[b] = w[b] + rb_factors_[b] * r[b];  // w + s·r, as written
  return out;
}

std::vector<double> RegionalError::standard_errors() const {
  const std::size_t n = grid_.count();
  const std::vector<double> none(n, 0.0);
  const std::vector<double> v_w = w_ ? variances(*w_) : none, v_r = r_ ? rb_variances() : none;
  std::vector<double> out(n);
  const bool field = regional_field_ && d_;
  const std::vector<double> v_u = field ? variances(*u_) : none, v_d = field ? variances(*d_) : none;
  const std::vector<double> r = field ? means(*r_) : none, d = field ? means(*d_) : none;
  for (std::size_t b = 0; b < n; ++b) {
    double v;
    if (field) {
      const RbShareMix mix = rb_share_mix(v_r[b], v_d[b], r[b], d[b]);
      const double lambda = mix.lambda, bias_squared = mix.bias_squared;
      const double cov_w_d = 0.5 * (v_u[b] - v_w[b] - v_d[b]);  // u = w + d
      // δ: the region's mean as written less the λ formula's (the w terms cancel)
      const double missed = rb_factors_[b] * r[b] - (lambda * r[b] + (1.0 - lambda) * d[b]);
      v = v_w[b] + lambda * lambda * (v_r[b] + bias_squared) + (1.0 - lambda) * (1.0 - lambda) * v_d[b] +
          2.0 * (1.0 - lambda) * cov_w_d + missed * missed;
    } else {
      v = v_w[b] + rb_factors_[b] * rb_factors_[b] * v_r[b];  // Var(w + s·r), independent layers
    }
    out[b] = std::isnan(v) ? v : std::sqrt(std::max(0.0, v));
  }
  return out;
}

std::vector<double> RegionalError::relative_standard_errors() const {
  const std::vector<double> mean = region_means(), se = standard_errors();
  std::vector<double> out(mean.size());
  for (std::size_t b = 0; b < out.size(); ++b) out[b] = mean[b] > 0.0 ? se[b] / mean[b] : std::nan("");
  return out;
}

double RegionalError::degrees_of_freedom() const {
  double least = INFINITY;
  for (const Track* t : tracks()) {
    const double own = double(t->estimate->batches()) - 1.0;
    if (own < 1.0) return 0.0;
    if (!t->per_pixel) {
      least = std::min(least, own + kRegionalRbPoolDegreesOfFreedom);  // RB's, pooled
      continue;
    }
    // PT's: per region, a sum of its pixels' variances, each with `own` degrees of freedom; the
    // sum's by Welch–Satterthwaite, ν (Σ V_p)² / Σ V_p² (region_totals' scales, 1/n and 1/n², cancel)
    const std::vector<double> var = t->estimate->variance_of_mean();
    std::vector<double> var_sq(var.size());
    for (std::size_t i = 0; i < var.size(); ++i) var_sq[i] = var[i] * var[i];
    const std::vector<double> sum = region_totals(*t, var, false), sum_sq = region_totals(*t, var_sq, true);
    for (std::size_t b = 0; b < sum.size(); ++b)
      if (sum_sq[b] > 0.0) least = std::min(least, own * sum[b] * sum[b] / sum_sq[b]);
  }
  return std::isfinite(least) ? least : 0.0;
}

double RegionalError::rb_batch_correlation() const {
  if (!r_) return std::nan("");
  const std::size_t n = grid_.count(), batches = r_->batch_means.size() / n;
  if (batches < 3) return std::nan("");
  // Pooled over the regions: Σ_b Σ_k (x_bk − x̄_b)(x_b,k+1 − x̄_b) / Σ_b Σ_k (x_bk − x̄_b)², each region
  // standardised by its own variance so that bright regions do not dominate.
  double num = 0.0, den_weight = 0.0;
  for (std::size_t b = 0; b < n; ++b) {
    double mean = 0.0;
    for (std::size_t k = 0; k < batches; ++k) mean += r_->batch_means[k * n + b];
    mean /= double(batches);
    double ss = 0.0, lag = 0.0;
    for (std::size_t k = 0; k < batches; ++k) {
      const double x = r_->batch_means[k * n + b] - mean;
      ss += x * x;
      if (k + 1 < batches) lag += x * (r_->batch_means[(k + 1) * n + b] - mean);
    }
    if (ss <= 0.0) continue;
    num += lag / ss;
    den_weight += 1.0;
  }
  return den_weight > 0.0 ? num / den_weight : std::nan("");
}

RegionalError::State RegionalError::state() const {
  State s;
  for (const Track* t : tracks()) s.layers.push_back(t->estimate->state());
  return s;
}

double expected_largest_error(const std::vector<double>& standard_deviations) {
  double largest = 0.0;
  std::vector<double> sigma;
  for (double s : standard_deviations)
    if (std::isfinite(s) && s > 0.0) {
      sigma.push_back(s);
      largest = std::max(largest, s);
    }
  if (sigma.empty()) return std::nan("");
  // ∫₀^∞ P(max_b |e_b| > t) dt by the midpoint rule to 10 σ_max (the tail beyond is below 1e-20).
  const int steps = 2000;
  const double dt = 10.0 * largest / steps;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double t = (i + 0.5) * dt;
    double all_within = 1.0;
    for (double s : sigma) all_within *= std::erf(t / (s * std::sqrt(2.0)));
    sum += (1.0 - all_within) * dt;
  }
  return sum;
}

}  // namespace bp

// Statistics for tests: chi-square goodness of fit with pooled cells, Šidák-corrected levels.
#pragma once
#include <cmath>
#include <vector>

namespace bp::test {

// Regularized upper incomplete gamma Q(a, x) (series for x < a+1, continued fraction otherwise).
inline double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double gln = std::lgamma(a);
  if (x < a + 1.0) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1.0;
      del *= x / ap;
      sum += del;
      if (std::fabs(del) < std::fabs(sum) * 1e-15) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
  }
  double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::fabs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

struct ChiSquareResult {
  double statistic = 0.0;
  int dof = 0;
  double p_value = 1.0;
};

// Pearson's test of observed counts against expected counts; cells with expected < min_expected
// are pooled together (pbrt's convention) so the chi-square approximation holds.
inline ChiSquareResult chi_square_test(const std::vector<double>& observed, const std::vector<double>& expected,
                                       double min_expected = 5.0) {
  ChiSquareResult r;
  double pooled_obs = 0.0, pooled_exp = 0.0;
  int cells = 0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < min_expected) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
      continue;
    }
    r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++cells;
  }
  if (pooled_exp > 0.0 || pooled_obs > 0.0) {
    // An impossible cell that received samples fails outright.
    if (pooled_exp <= 0.0) { r.p_value = 0.0; r.statistic = INFINITY; r.dof = cells; return r; }
    r.statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++cells;
  }
  r.dof = cells - 1;
  r.p_value = r.dof > 0 ? gamma_q(0.5 * r.dof, 0.5 * r.statistic) : 1.0;
  return r;
}

// Level of each of `tests` tests so that the family-wise level is alpha.
inline double sidak_alpha(double alpha, int tests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / tests); }

// Regularized incomplete beta I_x(a, b) (continued fraction, Numerical Recipes' betacf).
inline double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  auto cf = [](double a, double b, double x) {
    double qab = a + b, qap = a + 1.0, qam = a - 1.0, c = 1.0, d = 1.0 - qab * x / qap;
    if (std::fabs(d) < 1e-300) d = 1e-300;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m < 10000; ++m) {
      int m2 = 2 * m;
      double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
      d = 1.0 + aa * d; if (std::fabs(d) < 1e-300) d = 1e-300;
      c = 1.0 + aa / c; if (std::fabs(c) < 1e-300) c = 1e-300;
      d = 1.0 / d; h *= d * c;
      aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
      d = 1.0 + aa * d; if (std::fabs(d) < 1e-300) d = 1e-300;
      c = 1.0 + aa / c; if (std::fabs(c) < 1e-300) c = 1e-300;
      d = 1.0 / d;
      double del = d * c;
      h *= del;
      if (std::fabs(del - 1.0) < 1e-15) break;
    }
    return h;
  };
  double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * cf(a, b, x) / a;
  return 1.0 - front * cf(b, a, 1.0 - x) / b;
}

// Two-sided tail probability of Student's t with `dof` degrees of freedom.
inline double student_t_two_sided_p(double t, double dof) {
  return incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

// Two-sided z quantile for a tail probability p (bisection on erfc; tests only).
inline double z_for_two_sided(double p) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    if (std::erfc(mid / std::sqrt(2.0)) > p) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace bp::test

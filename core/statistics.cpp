#include "core/statistics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sylva {

namespace {

double gamma_p_series(double a, double x) {
  double sum = 1.0 / a, term = sum, ap = a;
  for (int n = 0; n < 10000; ++n) {
    ap += 1.0;
    term *= x / ap;
    sum += term;
    if (std::abs(term) < std::abs(sum) * 1e-15) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

double gamma_q_continued_fraction(double a, double x) {
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  if (x < a + 1.0) return 1.0 - gamma_p_series(a, x);
  return gamma_q_continued_fraction(a, x);
}

double chi2_survival(double x, double dof) { return gamma_q(0.5 * dof, 0.5 * x); }

Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected, double min_expected) {
  if (observed.size() != expected.size()) throw std::invalid_argument("chi2_test: size mismatch");
  Chi2Result r;
  double pool_obs = 0, pool_exp = 0;
  int bins = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < min_expected) {
      pool_obs += observed[i];
      pool_exp += expected[i];
      ++r.pooled_bins;
      continue;
    }
    r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++bins;
  }
  if (pool_exp >= min_expected) {
    r.statistic += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
    ++bins;
  } else if (pool_obs > pool_exp + 5.0 * std::sqrt(std::max(pool_exp, 1.0)) + 5.0) {
    // Samples where the pdf says there should be (almost) none: a clear failure.
    r.statistic = INFINITY;
  }
  r.dof = std::max(1, bins - 1);
  r.p_value = std::isinf(r.statistic) ? 0.0 : chi2_survival(r.statistic, r.dof);
  return r;
}

double sidak_alpha(double alpha, size_t tests) {
  return 1.0 - std::pow(1.0 - alpha, 1.0 / static_cast<double>(std::max<size_t>(1, tests)));
}

}  // namespace sylva

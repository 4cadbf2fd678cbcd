#pragma once
// Statistics used by Sylva's own verification: χ² goodness-of-fit (for every sampling routine) and
// its Šidák correction. Pure functions.

#include <cstddef>
#include <vector>

namespace sylva {

// Regularised upper incomplete gamma Q(a, x) (series / continued fraction, Numerical Recipes §6.2).
double gamma_q(double a, double x);
// P(X ≥ x) for X ~ χ²(dof).
double chi2_survival(double x, double dof);

struct Chi2Result {
  double statistic = 0;
  int dof = 0;
  double p_value = 1;
  int pooled_bins = 0;  // bins merged because their expected count was < min_expected
};

// Pearson's χ² of observed counts against expected counts (same total). Bins with expected count
// below `min_expected` are pooled into one (if that pool is itself too small it is merged into the
// smallest regular bin), as in Mitsuba's and pbrt's χ² tests.
Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected,
                     double min_expected = 5.0);

// Per-test significance for `tests` tests at family-wise level `alpha`: 1 − (1 − α)^(1/n).
double sidak_alpha(double alpha, size_t tests);

}  // namespace sylva

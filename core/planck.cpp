#include "core/planck.h"

#include "core/error.h"

#include <fmt/core.h>

#include <cmath>
#include <cstddef>

namespace sylva {

double planck_radiance(double lambda_nm, double temperature_k) {
  if (!(temperature_k > 0) || !(lambda_nm > 0)) return 0.0;
  const double lambda = lambda_nm * 1e-9;
  const double x = kPlanckC2 / (lambda * temperature_k);
  // Per metre of wavelength, then per nanometre.
  return kPlanckC1L / (std::pow(lambda, 5) * std::expm1(x)) * 1e-9;
}

double planck_radiance_dt(double lambda_nm, double temperature_k) {
  if (!(temperature_k > 0) || !(lambda_nm > 0)) return 0.0;
  const double lambda = lambda_nm * 1e-9;
  const double x = kPlanckC2 / (lambda * temperature_k);
  // dB/dT = B · x/T · eˣ/(eˣ − 1) = B · x/T / (1 − e⁻ˣ).
  return planck_radiance(lambda_nm, temperature_k) * x / temperature_k / -std::expm1(-x);
}

void check_response(const SpectralResponse& s, const char* what) {
  if (s.lambda_nm.size() != s.weight.size() || s.lambda_nm.size() < 2)
    throw Error(fmt::format("{}: a spectral response needs at least two (wavelength, weight) pairs", what));
  double area = 0;
  for (size_t i = 0; i < s.lambda_nm.size(); ++i) {
    if (!(s.lambda_nm[i] > 0) || !std::isfinite(s.lambda_nm[i]) || !(s.weight[i] >= 0) || !std::isfinite(s.weight[i]))
      throw Error(fmt::format("{}: point {} of the spectral response is not a positive wavelength with a weight ≥ 0",
                              what, i + 1));
    if (i > 0) {
      if (!(s.lambda_nm[i] > s.lambda_nm[i - 1]))
        throw Error(fmt::format("{}: the response's wavelengths must increase (point {})", what, i + 1));
      area += 0.5 * (s.weight[i] + s.weight[i - 1]) * (s.lambda_nm[i] - s.lambda_nm[i - 1]);
    }
  }
  if (!(area > 0)) throw Error(fmt::format("{}: the spectral response has zero integral", what));
}

namespace {

// ∫ S f dλ / ∫ S dλ by the trapezoid rule over the table's points.
template <class F>
double band_mean(const SpectralResponse& s, F f) {
  double num = 0, den = 0;
  double f_prev = f(s.lambda_nm[0]);
  for (size_t i = 1; i < s.lambda_nm.size(); ++i) {
    const double f_i = f(s.lambda_nm[i]);
    const double h = 0.5 * (s.lambda_nm[i] - s.lambda_nm[i - 1]);
    num += h * (s.weight[i] * f_i + s.weight[i - 1] * f_prev);
    den += h * (s.weight[i] + s.weight[i - 1]);
    f_prev = f_i;
  }
  return num / den;
}

}  // namespace

double band_planck_radiance(const SpectralResponse& s, double temperature_k) {
  return band_mean(s, [&](double l) { return planck_radiance(l, temperature_k); });
}

double brightness_temperature(const SpectralResponse& s, double band_radiance) {
  if (!(band_radiance > 0)) return 0.0;
  double lo = 1.0, hi = 1.0e4;
  if (band_radiance > band_planck_radiance(s, hi))
    throw Error(fmt::format("band radiance {} is above a 10⁴ K blackbody's in this band", band_radiance));
  if (band_radiance < band_planck_radiance(s, lo)) return lo;
  double t = 300.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double f = band_planck_radiance(s, t) - band_radiance;
    if (f > 0)
      hi = t;
    else
      lo = t;
    const double df = band_mean(s, [&](double l) { return planck_radiance_dt(l, t); });
    double next = df > 0 ? t - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    if (std::abs(next - t) <= 1e-9 * next) return next;
    t = next;
  }
  return t;
}

}  // namespace sylva

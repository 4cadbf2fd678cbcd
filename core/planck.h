#pragma once
// Planck's law and brightness temperature: the blackbody radiance the thermal bands will carry
// (issue 42; docs/thermal.md). Constants are CODATA 2018 (exact SI values of h, c and k).
//
// B_λ(λ, T) = 2hc² / λ⁵ · 1 / (exp(hc / (λ k T)) − 1)        W·m⁻²·sr⁻¹ per metre of wavelength
//
// A band's radiance is the response-weighted mean ∫ S B dλ / ∫ S dλ over a tabulated spectral
// response S (the form of the Landsat TIRS calibration, per unit wavelength); its brightness
// temperature is the T whose band radiance equals a given one. The band radiance is strictly
// increasing in T, so the inverse is unique.

#include <span>

namespace sylva {

inline constexpr double kPlanckC1L = 1.191042972e-16;       // 2hc², W·m²·sr⁻¹
inline constexpr double kPlanckC2 = 1.438776877e-2;         // hc/k, m·K
inline constexpr double kStefanBoltzmann = 5.670374419e-8;  // σ, W·m⁻²·K⁻⁴

// Spectral radiance of a blackbody at `lambda_nm` and `temperature_k`, W·m⁻²·sr⁻¹·nm⁻¹; 0 for
// T ≤ 0.
double planck_radiance(double lambda_nm, double temperature_k);
// Its derivative with respect to temperature, W·m⁻²·sr⁻¹·nm⁻¹·K⁻¹.
double planck_radiance_dt(double lambda_nm, double temperature_k);

// A spectral response tabulated at increasing wavelengths (nm), weights ≥ 0 with a positive
// trapezoid integral; throws Error otherwise (`what` names the caller's band in the message).
struct SpectralResponse {
  std::span<const double> lambda_nm;
  std::span<const double> weight;
};
void check_response(const SpectralResponse& s, const char* what);

// The band radiance of a blackbody at `temperature_k`: trapezoid rule over the table's points.
double band_planck_radiance(const SpectralResponse& s, double temperature_k);
// The brightness temperature of `band_radiance` (W·m⁻²·sr⁻¹·nm⁻¹) through the band: the T with
// band_planck_radiance(s, T) = band_radiance, to 1e-9 relative (Newton's method inside a bisection
// bracket of [1 K, 10⁴ K]); 0 for a radiance ≤ 0. Throws Error above the bracket.
double brightness_temperature(const SpectralResponse& s, double band_radiance);

}  // namespace sylva

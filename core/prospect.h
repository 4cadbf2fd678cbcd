#pragma once
// PROSPECT-D leaf optical properties (Féret, Gitelson, Noble & Jacquemoud 2017, RSE 193:204-215):
// a leaf is a pile of N absorbing plates (Allen et al. 1969; Stokes 1862). The result is the
// directional-hemispherical reflectance and transmittance of the leaf for light incident within a
// 40° solid angle, at 1 nm from 400 to 2500 nm. Deterministic; computed in double, stored as float.
// Coefficients: data/prospect/prospect_d_spectra.txt (read once per process, thread-safe).

#include <span>
#include <vector>

namespace sylva {

// Leaf biochemistry, in PROSPECT's units.
struct ProspectParams {
  float N = 1.5f;     // leaf structure parameter (number of plates), ≥ 1
  float Cab = 40;     // chlorophyll a+b, µg/cm²
  float Car = 8;      // carotenoids, µg/cm²
  float Ant = 0;      // anthocyanins, µg/cm²
  float Cbrown = 0;   // brown pigments, arbitrary units
  float Cw = 0.01f;   // equivalent water thickness, cm (= g/cm²)
  float Cm = 0.009f;  // dry matter per area, g/cm²
};

// Spectral leaf optics on a common wavelength grid; reflectance + transmittance ≤ 1.
struct LeafOptics {
  std::vector<float> lambda_nm;
  std::vector<float> reflectance;
  std::vector<float> transmittance;
};

// PROSPECT-D at 400–2500 nm, 1 nm (2101 samples). Throws sylva::Error for N < 1, negative or
// non-finite contents, or an unreadable coefficient table.
LeafOptics prospect_d(const ProspectParams& params);

// The generalized plate model behind every PROSPECT version: given per-wavelength refractive index
// n and total absorption coefficient K = Σ C_i·k_i / N (per plate), returns R and T of N plates.
// Lets tests and other PROSPECT versions (5, PRO) reuse the same physics.
LeafOptics prospect_plate_model(std::span<const float> lambda_nm, std::span<const double> n,
                                std::span<const double> absorption, double N);

// Average transmissivity of a dielectric interface (relative index n) for isotropic light within
// the cone of half-angle alpha_deg (Stern 1964; Allen 1973). 0 < alpha_deg ≤ 90.
double prospect_tav(double alpha_deg, double n);

// Exponential integral E1(x) = ∫_x^∞ e^{-t}/t dt for x > 0 (relative error < 1e-14).
double exponential_integral_e1(double x);

}  // namespace sylva

#pragma once
// A spectral clear sky: Preetham, Shirley & Smits 1999, "A Practical Analytic Model for Daylight"
// (SIGGRAPH '99). Scene file: [sky] model = "preetham", turbidity = T (1.7–10).
//
// Luminance Y and chromaticity (x, y) over the dome follow Perez et al.'s (1993) all-weather
// formula F(θ, γ) = (1 + A e^{B/cos θ})(1 + C e^{Dγ} + E cos²γ), with the turbidity-dependent
// coefficients and zenith values of Preetham et al. Appendix A.2; each direction's spectrum is the
// CIE daylight of its chromaticity, S0 + M1·S1 + M2·S2 (CIE 15:2004 §3.1, Preetham §A.3), scaled to
// its luminance. So the sky is blue overhead, whiter near the horizon and the sun, and warmer when
// the sun is low.
//
// Near infrared (the daylight basis ends at 830 nm and the chromaticity only constrains 380–780 nm):
// beyond 780 nm each direction keeps its 780 nm value times f(λ)/f(780 nm) with
//   f(λ) = E_direct(λ)·[(λ/550)^−4.08 + (T − 1)(λ/550)^−1.3],
// the single-scattering sky of an optically thin atmosphere — the beam at the ground (ASTM G173
// direct, so the water and oxygen bands appear in the sky too) times the scattering optical depth,
// Rayleigh (λ^−4.08, Bucholtz 1995) plus aerosol (Ångström λ^−1.3), their ratio at 550 nm T − 1 by
// the definition of turbidity T = (τ_R + τ_a)/τ_R. Above 780 nm τ_R < 0.02 and τ_a ≲ 0.1, where the
// thin-atmosphere limit holds (docs/radiometry.md, "Spectral clear sky").
//
// Normalisation (like the CIE sky): `spectrum` is the horizontal diffuse irradiance. Given in the
// scene file, the sky matches it at every wavelength (the model then sets how each wavelength is
// spread over the dome); omitted, the sky keeps the model's own spectrum, scaled so its
// 300–2500 nm horizontal irradiance equals ASTM G173 diffuse's (× `scale`).

#include "core/math.h"
#include "core/params.h"
#include "core/spectrum.h"

#include <array>
#include <string_view>

namespace sylva {

struct PreethamSky {
  static constexpr std::string_view kType = "preetham";
  static constexpr bool kNormalisedToHorizontal = true;
  static constexpr bool kUpperHemisphereOnly = true;

  float turbidity = 3.0f;    // T = (τ_Rayleigh + τ_aerosol)/τ_Rayleigh; 2 very clear, 3 clear, 6+ hazy
  bool own_spectrum = true;  // no `spectrum` given: keep the model's spectral shape (see above)

  static PreethamSky create(const Params& params);
  DenseSpectrum default_spectrum() const { return astm_g173_diffuse(); }
  // Luminance relative to the zenith's (the sampling map); 0 below the horizon.
  float relative_radiance(const Vec3& dir, const Vec3& sun_dir) const;
  // The spectral radiance in direction `dir` is Σ w_i·basis()[i](λ) (relative units: the
  // luminance relative to the zenith, per unit luminance of the basis combination).
  Vec3 basis_weights(const Vec3& dir, const Vec3& sun_dir) const;
  // The CIE daylight basis S0, S1, S2 (data/cie_daylight_components_10nm.csv) on the 1 nm grid,
  // extended beyond 780 nm as above for this turbidity.
  std::array<DenseSpectrum, 3> basis() const;
};

// CIE chromaticity (x, y) and relative luminance of the Preetham sky in direction `dir`, Y relative
// to the zenith; for tests and previews.
Vec3 preetham_xyY(float turbidity, const Vec3& dir, const Vec3& sun_dir);

}  // namespace sylva

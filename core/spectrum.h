#pragma once
// Spectra. Wavelengths in nanometres; radiance in W·m⁻²·sr⁻¹·nm⁻¹ (docs/design.md §4).
//
// Every spectrum the renderer evaluates per hit is resampled once onto a dense 1 nm grid over
// [kLambdaMin, kLambdaMax], so evaluation is one lerp. Paths carry kLambdaCount wavelengths at
// once (hero wavelength sampling, Wilkie et al. 2014).

#include "core/math.h"

#include <emmintrin.h>  // SSE2 only: the x86-64 baseline (docs/design.md §10, "Build cost")

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

inline constexpr float kLambdaMin = 300.0f;
inline constexpr float kLambdaMax = 2500.0f;
inline constexpr int kLambdaSamples = static_cast<int>(kLambdaMax - kLambdaMin) + 1;
inline constexpr int kLambdaCount = 4;

// A value per carried wavelength (throughput, radiance, reflectance).
using SampledSpectrum = glm::vec4;
static_assert(kLambdaCount == 4, "SampledSpectrum is a vec4");

inline float max_component(const SampledSpectrum& s) { return std::max(std::max(s.x, s.y), std::max(s.z, s.w)); }
inline float average(const SampledSpectrum& s) { return 0.25f * (s.x + s.y + s.z + s.w); }
inline bool is_black(const SampledSpectrum& s) { return s.x == 0 && s.y == 0 && s.z == 0 && s.w == 0; }

// The carried wavelengths and the probability density each was drawn with (per nm).
struct SampledWavelengths {
  SampledSpectrum lambda_nm{550.0f};
  SampledSpectrum pdf{1.0f};
};

// What a tabulated spectrum is outside its table.
enum class Extrapolate { Zero, Clamp };

// Where λ falls on the dense 1 nm grid: the sample below (clamped to the grid) and the fraction
// towards the next, for a lerp of grid values.
struct GridPosition {
  int index;
  float fraction;
};
inline GridPosition grid_position(float lambda_nm) {
  const float x = std::clamp(lambda_nm - kLambdaMin, 0.0f, static_cast<float>(kLambdaSamples - 1));
  const int i = std::min(static_cast<int>(x), kLambdaSamples - 2);
  return {i, x - static_cast<float>(i)};
}
// grid_position of the four carried wavelengths, computed side by side (the same values): every
// spectral lookup of a path vertex starts here (bench/README.md, "Four at a time").
struct GridPositions {
  alignas(16) int32_t index[kLambdaCount];
  SampledSpectrum fraction;
};
inline GridPositions grid_positions(const SampledWavelengths& wl) {
  const __m128 x =
      _mm_min_ps(_mm_max_ps(_mm_setzero_ps(), _mm_sub_ps(_mm_loadu_ps(&wl.lambda_nm[0]), _mm_set1_ps(kLambdaMin))),
                 _mm_set1_ps(static_cast<float>(kLambdaSamples - 1)));
  // x ≥ 0, so truncating min(x, n − 2) is min(truncated x, n − 2).
  const __m128i i = _mm_cvttps_epi32(_mm_min_ps(x, _mm_set1_ps(static_cast<float>(kLambdaSamples - 2))));
  GridPositions g;
  _mm_store_si128(reinterpret_cast<__m128i*>(g.index), i);
  _mm_storeu_ps(&g.fraction[0], _mm_sub_ps(x, _mm_cvtepi32_ps(i)));
  return g;
}
// The lerp of grid values at the four positions: values[i] + f · (values[i + 1] − values[i]).
inline SampledSpectrum grid_lerp(const float* values, const GridPositions& g) {
  const SampledSpectrum a(values[g.index[0]], values[g.index[1]], values[g.index[2]], values[g.index[3]]);
  const SampledSpectrum b(values[g.index[0] + 1], values[g.index[1] + 1], values[g.index[2] + 1],
                          values[g.index[3] + 1]);
  return a + g.fraction * (b - a);
}

class DenseSpectrum {
 public:
  DenseSpectrum() : values_(kLambdaSamples, 0.0f) {}
  static DenseSpectrum constant(float value);
  // Piecewise-linear through (lambda_nm[i], value[i]) (sorted ascending), averaged over each 1 nm
  // bin's neighbourhood so finer tables are not aliased. NaN entries are skipped.
  static DenseSpectrum from_samples(const std::vector<double>& lambda_nm, const std::vector<double>& value,
                                    Extrapolate outside);

  float eval(float lambda_nm) const {
    const auto [i, f] = grid_position(lambda_nm);
    return values_[i] + f * (values_[i + 1] - values_[i]);
  }
  SampledSpectrum eval(const SampledWavelengths& wl) const { return eval(grid_positions(wl)); }
  SampledSpectrum eval(const GridPositions& g) const { return grid_lerp(values_.data(), g); }

  // ∫ value dλ over the grid (trapezoid, nm).
  double integral() const;
  // ∫ this·other dλ.
  double integral_product(const DenseSpectrum& other) const;
  float min_value() const;
  float max_value() const;

  float& operator[](int i) { return values_[i]; }
  float operator[](int i) const { return values_[i]; }
  static float grid_lambda(int i) { return kLambdaMin + static_cast<float>(i); }

  DenseSpectrum& operator*=(float s);
  friend DenseSpectrum operator*(const DenseSpectrum& a, const DenseSpectrum& b);
  friend DenseSpectrum operator+(const DenseSpectrum& a, const DenseSpectrum& b);
  friend DenseSpectrum operator-(const DenseSpectrum& a, const DenseSpectrum& b);

 private:
  std::vector<float> values_;
};

// Loads one column of a data table as a spectrum (first column = wavelength in nm).
DenseSpectrum load_spectrum(const std::filesystem::path& table, const std::string& column, Extrapolate outside);

// The standard spectra Sylva ships (data/), loaded once and cached. Thread-safe.
const DenseSpectrum& cie_x();
const DenseSpectrum& cie_y();
const DenseSpectrum& cie_z();
// ASTM G173-03 direct normal + circumsolar irradiance, W·m⁻²·nm⁻¹.
const DenseSpectrum& astm_g173_direct();
// ASTM G173-03 global on the 37° sun-facing tilt, W·m⁻²·nm⁻¹.
const DenseSpectrum& astm_g173_global();
// The default diffuse-sky spectrum: ASTM G173 global (37° tilt) minus the direct beam projected on
// that tilt (incidence 11.2° at the standard's solar zenith 48.2°), clamped at 0.
DenseSpectrum astm_g173_diffuse();
// A built-in spectrum by the name parameter files use ("astm-g173-direct", "astm-g173-diffuse",
// "astm-g173-global"); nullopt for any other name.
std::optional<DenseSpectrum> named_spectrum(std::string_view name);

}  // namespace sylva

#pragma once
// Spectra. Wavelengths in nanometres; radiance in W·m⁻²·sr⁻¹·nm⁻¹ (docs/design.md §4).
//
// Every spectrum the renderer evaluates per hit is resampled once onto a dense 1 nm grid over
// [kLambdaMin, kLambdaMax], so evaluation is one lerp. Paths carry kLambdaCount wavelengths at
// once (hero wavelength sampling, Wilkie et al. 2014).

#include "core/math.h"

#include <emmintrin.h>  // SSE2 only: the x86-64 baseline (docs/design.md §10, "Build cost")

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

inline constexpr float kLambdaMin = 300.0f;
inline constexpr float kLambdaMax = 2500.0f;
inline constexpr int kLambdaSamples = static_cast<int>(kLambdaMax - kLambdaMin) + 1;
// Paths carry kLambdaCount wavelengths in kLambdaBlocks blocks of four (one SSE register each).
// The blocks are shared among the requested bands (WavelengthSampler, core/band.h): with one band
// every block serves it, with several each band has at least one block of its own.
inline constexpr int kLambdaBlocks = 4;
inline constexpr int kLambdaCount = 4 * kLambdaBlocks;

// A value per carried wavelength (throughput, radiance, reflectance): kLambdaBlocks glm::vec4 and
// the element-wise arithmetic of glm's vectors.
class SampledSpectrum {
 public:
  SampledSpectrum() : SampledSpectrum(0.0f) {}
  explicit SampledSpectrum(float v) { v_.fill(glm::vec4(v)); }
  // The same four values in every block.
  explicit SampledSpectrum(const glm::vec4& block) { v_.fill(block); }

  float& operator[](int i) { return v_[static_cast<size_t>(i >> 2)][i & 3]; }
  float operator[](int i) const { return v_[static_cast<size_t>(i >> 2)][i & 3]; }
  glm::vec4& block(int b) { return v_[static_cast<size_t>(b)]; }
  const glm::vec4& block(int b) const { return v_[static_cast<size_t>(b)]; }

#define SYLVA_SPECTRUM_OP(op)                                                                            \
  SampledSpectrum& operator op##=(const SampledSpectrum& o) {                                            \
    for (size_t b = 0; b < kLambdaBlocks; ++b) v_[b] op## = o.v_[b];                                     \
    return *this;                                                                                        \
  }                                                                                                      \
  SampledSpectrum& operator op##=(float s) {                                                             \
    for (size_t b = 0; b < kLambdaBlocks; ++b) v_[b] op## = s;                                           \
    return *this;                                                                                        \
  }                                                                                                      \
  friend SampledSpectrum operator op(SampledSpectrum a, const SampledSpectrum& b) { return a op## = b; } \
  friend SampledSpectrum operator op(SampledSpectrum a, float s) { return a op## = s; }                  \
  friend SampledSpectrum operator op(float s, const SampledSpectrum& a) {                                \
    SampledSpectrum r(s);                                                                                \
    return r op## = a;                                                                                   \
  }
  SYLVA_SPECTRUM_OP(+)
  SYLVA_SPECTRUM_OP(-)
  SYLVA_SPECTRUM_OP(*)
  SYLVA_SPECTRUM_OP(/)
#undef SYLVA_SPECTRUM_OP
  friend SampledSpectrum operator-(SampledSpectrum a) {
    for (size_t b = 0; b < kLambdaBlocks; ++b) a.v_[b] = -a.v_[b];
    return a;
  }
  friend bool operator==(const SampledSpectrum& a, const SampledSpectrum& b) { return a.v_ == b.v_; }

 private:
  std::array<glm::vec4, kLambdaBlocks> v_;
};

// Element-wise max(s, 0).
inline SampledSpectrum clamp_zero(SampledSpectrum s) {
  for (int b = 0; b < kLambdaBlocks; ++b) s.block(b) = glm::max(s.block(b), glm::vec4(0.0f));
  return s;
}
inline float max_component(const SampledSpectrum& s) {
  glm::vec4 m = s.block(0);
  for (int b = 1; b < kLambdaBlocks; ++b) m = glm::max(m, s.block(b));
  return std::max(std::max(m.x, m.y), std::max(m.z, m.w));
}
inline float min_component(const SampledSpectrum& s) {
  glm::vec4 m = s.block(0);
  for (int b = 1; b < kLambdaBlocks; ++b) m = glm::min(m, s.block(b));
  return std::min(std::min(m.x, m.y), std::min(m.z, m.w));
}
inline float average(const SampledSpectrum& s) {
  glm::vec4 m = s.block(0);
  for (int b = 1; b < kLambdaBlocks; ++b) m += s.block(b);
  return (m.x + m.y + m.z + m.w) * (1.0f / kLambdaCount);
}
inline bool is_black(const SampledSpectrum& s) {
  for (int b = 0; b < kLambdaBlocks; ++b)
    if (s.block(b) != glm::vec4(0.0f)) return false;
  return true;
}
inline bool all_finite(const SampledSpectrum& s) {
  bool finite = true;
  for (int i = 0; i < kLambdaCount; ++i) finite &= std::isfinite(s[i]);
  return finite;
}

// The carried wavelengths and the probability density each was drawn with (per nm).
struct SampledWavelengths {
  SampledSpectrum lambda_nm{550.0f};
  SampledSpectrum pdf{1.0f};
  // The hero: the lane whose free flights the haze samples, every lane equally likely whatever the
  // wavelengths (the one-sample MIS over lanes in Haze::sample_scattering needs that; the lanes of
  // different band groups are not interchangeable).
  int hero = 0;
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
// grid_position of the carried wavelengths, computed four side by side (the same values): every
// spectral lookup of a path vertex starts here (bench/README.md, "Four at a time").
struct GridPositions {
  alignas(16) int32_t index[kLambdaCount];
  SampledSpectrum fraction;
};
inline GridPositions grid_positions(const SampledWavelengths& wl) {
  GridPositions g;
  for (int b = 0; b < kLambdaBlocks; ++b) {
    const __m128 x = _mm_min_ps(
        _mm_max_ps(_mm_setzero_ps(), _mm_sub_ps(_mm_loadu_ps(&wl.lambda_nm.block(b)[0]), _mm_set1_ps(kLambdaMin))),
        _mm_set1_ps(static_cast<float>(kLambdaSamples - 1)));
    // x ≥ 0, so truncating min(x, n − 2) is min(truncated x, n − 2).
    const __m128i i = _mm_cvttps_epi32(_mm_min_ps(x, _mm_set1_ps(static_cast<float>(kLambdaSamples - 2))));
    _mm_store_si128(reinterpret_cast<__m128i*>(g.index + 4 * b), i);
    _mm_storeu_ps(&g.fraction.block(b)[0], _mm_sub_ps(x, _mm_cvtepi32_ps(i)));
  }
  return g;
}
// The lerp of grid values at the carried positions: values[i] + f · (values[i + 1] − values[i]).
inline SampledSpectrum grid_lerp(const float* values, const GridPositions& g) {
  SampledSpectrum out;
  for (int b = 0; b < kLambdaBlocks; ++b) {
    const int32_t* i = g.index + 4 * b;
    const glm::vec4 lo(values[i[0]], values[i[1]], values[i[2]], values[i[3]]);
    const glm::vec4 hi(values[i[0] + 1], values[i[1] + 1], values[i[2] + 1], values[i[3] + 1]);
    out.block(b) = lo + g.fraction.block(b) * (hi - lo);
  }
  return out;
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

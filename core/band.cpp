#include "core/band.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/simd.h"
#include "core/table.h"

#include <emmintrin.h>  // SSE2 only: the x86-64 baseline (docs/design.md §10, "Build cost")
#include <algorithm>
#include <bit>
#include <cmath>

namespace sylva {

namespace {

DenseSpectrum normalised(const DenseSpectrum& s) {
  DenseSpectrum r = s;
  const double integral = s.integral();
  if (!(integral > 0)) throw Error("spectral response has zero integral");
  r *= static_cast<float>(1.0 / integral);
  return r;
}

struct SrfSource {
  const char* prefix;  // band name prefix, e.g. "S2A_"
  const char* file;
};
constexpr SrfSource kSatellites[] = {
    {"S2A_", "srf/Sentinel_2A_Spectral_Response.tsv"},
    {"S2B_", "srf/Sentinel_2B_Spectral_Response.tsv"},
    {"L8_", "srf/Landsat_8_Spectral_Response.tsv"},
    {"L9_", "srf/Landsat_9_Spectral_Response.tsv"},
};
struct CameraBand {
  const char* name;
  const char* column;
};
constexpr CameraBand kCameraBands[] = {
    {"nir", "Basler_acA2500-20gm_850nm_filt"},
    {"red_edge", "Basler_acA2500-20gm_730nm_filt"},
    {"mono", "Basler_acA2500-20gm_mono"},
};
constexpr const char* kCameraFile = "srf/helios_camera_nir_srf.csv";

// Landsat 8/9 OLI band numbers → the SRF table's column names.
constexpr std::pair<const char*, const char*> kLandsatBands[] = {
    {"B1", "CoastalAerosol"}, {"B2", "Blue"},  {"B3", "Green"}, {"B4", "Red"},    {"B5", "NIR"},
    {"B6", "SWIR1"},          {"B7", "SWIR2"}, {"B8", "Pan"},   {"B9", "Cirrus"},
};

std::string srf_column(const std::string& prefix, const std::string& band) {
  if (prefix == "L8_" || prefix == "L9_")
    for (const auto& [number, column] : kLandsatBands)
      if (band == number) return column;
  return band;
}

}  // namespace

Band make_rgb_band() {
  // XYZ normalised by ∫ȳ so an equal-energy spectrum of 1 has Y = 1; then XYZ → linear Rec.709
  // (IEC 61966-2-1 matrix).
  const float k = static_cast<float>(1.0 / cie_y().integral());
  constexpr float m[3][3] = {{3.2404542f, -1.5371385f, -0.4985314f},
                             {-0.9692660f, 1.8760108f, 0.0415560f},
                             {0.0556434f, -0.2040259f, 1.0572252f}};
  Band b;
  b.name = "rgb";
  b.channels = {"R", "G", "B"};
  for (const auto& row : m) {
    DenseSpectrum w;
    for (int i = 0; i < kLambdaSamples; ++i)
      w[i] = k * (row[0] * cie_x()[i] + row[1] * cie_y()[i] + row[2] * cie_z()[i]);
    b.weights.push_back(w);
  }
  b.importance = normalised(cie_x() + cie_y() + cie_z());
  b.source = "CIE 1931 2-degree colour-matching functions (data/cie1931_2deg_cmf_1nm.csv) -> linear Rec.709, D65";
  return b;
}

Band make_srf_band(const std::string& name, const DenseSpectrum& response_in) {
  // Measured responses carry small negative noise floors (e.g. Landsat OLI's RSR tables); a
  // response cannot be negative, so those values are set to zero.
  DenseSpectrum response = response_in;
  for (int i = 0; i < kLambdaSamples; ++i) response[i] = std::max(0.0f, response[i]);
  Band b;
  b.name = name;
  b.channels = {name + ".Y"};
  b.weights = {normalised(response)};
  b.importance = b.weights[0];
  return b;
}

Band load_band(const std::string& name, const std::filesystem::path& file, const std::string& column) {
  Band b = make_srf_band(name, load_spectrum(file, column, Extrapolate::Zero));
  b.source = file.filename().string() + ", column " + column;
  return b;
}

ChannelSummary summarise_channel(const DenseSpectrum& weight) {
  DenseSpectrum s;
  for (int i = 0; i < kLambdaSamples; ++i) s[i] = std::max(0.0f, weight[i]);
  ChannelSummary out;
  const double area = s.integral(), peak = s.max_value();
  if (!(area > 0)) return out;
  DenseSpectrum lambda;
  for (int i = 0; i < kLambdaSamples; ++i) lambda[i] = kLambdaMin + static_cast<float>(i);
  out.centre_nm = s.integral_product(lambda) / area;
  out.equivalent_width_nm = area / peak;
  // Outermost half-maximum crossings, interpolated between 1 nm samples.
  const double half = 0.5 * peak;
  int lo = 0, hi = kLambdaSamples - 1;
  while (s[lo] < half) ++lo;
  while (s[hi] < half) --hi;
  const double left = lo == 0 ? kLambdaMin : kLambdaMin + lo - (s[lo] - half) / (s[lo] - s[lo - 1]);
  const double right =
      hi == kLambdaSamples - 1 ? kLambdaMin + hi : kLambdaMin + hi + (s[hi] - half) / (s[hi] - s[hi + 1]);
  out.fwhm_nm = right - left;
  return out;
}

std::vector<std::string> known_band_names() {
  std::vector<std::string> names = {"rgb"};
  for (const auto& c : kCameraBands) names.emplace_back(c.name);
  for (const auto& s : kSatellites) {
    const Table t = read_table(data_file(s.file));
    if (std::string(s.prefix)[0] == 'L') {
      for (const auto& [number, column] : kLandsatBands) names.push_back(s.prefix + std::string(number));
    } else {
      for (size_t c = 1; c < t.header.size(); ++c) names.push_back(s.prefix + t.header[c]);
    }
  }
  return names;
}

Band resolve_band(const std::string& name) {
  if (name == "rgb") return make_rgb_band();
  for (const auto& c : kCameraBands)
    if (name == c.name) return load_band(name, data_file(kCameraFile), c.column);
  for (const auto& s : kSatellites) {
    const std::string prefix = s.prefix;
    if (name.rfind(prefix, 0) == 0) {
      const Table t = read_table(data_file(s.file));
      const std::string column = srf_column(prefix, name.substr(prefix.size()));
      for (size_t c = 1; c < t.header.size(); ++c)
        if (t.header[c] == column) {
          Band b = make_srf_band(name, DenseSpectrum::from_samples(t.columns[0], t.columns[c], Extrapolate::Zero));
          b.source = std::filesystem::path(s.file).filename().string() + ", column " + column;
          return b;
        }
    }
  }
  std::string list;
  for (const auto& n : known_band_names()) list += (list.empty() ? "" : ", ") + n;
  throw Error("unknown band '" + name + "' (known: " + list + ")");
}

WavelengthSampler::WavelengthSampler(const std::vector<Band>& bands) {
  std::vector<float> w(kLambdaSamples - 1, 0.0f);
  for (const Band& b : bands)
    for (int i = 0; i + 1 < kLambdaSamples; ++i) w[i] += 0.5f * (b.importance[i] + b.importance[i + 1]);
  // The table spans the 1 nm bins from the first to the last with importance: the same density in a
  // table a third the size for the rgb and nir bands.
  const auto first = std::find_if(w.begin(), w.end(), [](float x) { return x > 0; });
  if (first != w.end()) {
    const auto last = std::find_if(w.rbegin(), w.rend(), [](float x) { return x > 0; }).base();
    lo_nm_ = kLambdaMin + static_cast<float>(first - w.begin());
    w = std::vector<float>(first, last);
  }
  const int n = static_cast<int>(w.size());
  std::vector<DistributionBin> table(n + 1);
  std::vector<uint32_t> guide(n);
  Distribution1D::tabulate(w.data(), n, table.data(), guide.data());
  cdf_.resize(n + 1);
  for (int i = 0; i <= n; ++i) cdf_[i] = table[i].cdf;
  // Each cell's first bin: the bin with mass whose [cdf, next cdf) holds the cell's start.
  const auto next_with_mass = [&](int i) {
    while (i < n && !(cdf_[i + 1] > cdf_[i])) ++i;
    return i;  // n: none
  };
  cells_.resize(kCells);
  int bin = next_with_mass(0);
  for (int k = 0; k < kCells; ++k) {
    const float u0 = static_cast<float>(k) / kCells;
    while (bin + 1 < n && cdf_[bin + 1] <= u0) bin = next_with_mass(bin + 1);
    const int second = next_with_mass(bin + 1);
    cells_[k] = Cell{cdf_[bin], second < n ? cdf_[second] : 1.0f, second < n ? cdf_[second + 1] : 1.0f,
                     static_cast<uint16_t>(bin), static_cast<uint16_t>(second < n ? second : bin)};
  }
}

SampledWavelengths WavelengthSampler::sample(float u) const {
  // The four hero wavelengths side by side in one SSE register each step (bench/README.md, "Four
  // at a time"): the same operations as one wavelength at a time, so the same bits.
  // u_k = u + k/4, wrapped into [0, 1).
  const __m128 v = _mm_add_ps(_mm_set1_ps(u), _mm_setr_ps(0.0f, 0.25f, 0.5f, 0.75f));
  const __m128 wrap = _mm_cmpge_ps(v, _mm_set1_ps(1.0f));
  const __m128 uk = simd::select(wrap, _mm_sub_ps(v, _mm_set1_ps(1.0f)), v);
  // Each u_k's cell (u_k < 1, so the index stays below kCells), loaded together so the misses
  // overlap, then transposed: cdf0, cdf1, end1 and the two bins of each wavelength's cell.
  alignas(16) int32_t index[kLambdaCount];
  _mm_store_si128(reinterpret_cast<__m128i*>(index), _mm_cvttps_epi32(_mm_mul_ps(uk, _mm_set1_ps(kCells))));
  __m128 cdf0 = _mm_loadu_ps(&cells_[index[0]].cdf0);
  __m128 cdf1 = _mm_loadu_ps(&cells_[index[1]].cdf0);
  __m128 end1 = _mm_loadu_ps(&cells_[index[2]].cdf0);
  __m128 bins = _mm_loadu_ps(&cells_[index[3]].cdf0);
  _MM_TRANSPOSE4_PS(cdf0, cdf1, end1, bins);
  // The bin holding u_k is the cell's first or its second (bin0 in the low, bin1 in the high half
  // of the last word).
  const __m128 second = _mm_cmpge_ps(uk, cdf1);
  const __m128i bin_pair = _mm_castps_si128(bins);
  const __m128i bin_mask = _mm_castps_si128(second);
  const __m128i bin = _mm_or_si128(_mm_and_si128(bin_mask, _mm_srli_epi32(bin_pair, 16)),
                                   _mm_andnot_si128(bin_mask, _mm_and_si128(bin_pair, _mm_set1_epi32(0xffff))));
  __m128 lo = simd::select(second, cdf1, cdf0);
  __m128 hi = simd::select(second, end1, cdf1);
  alignas(16) int32_t bin_k[kLambdaCount];
  _mm_store_si128(reinterpret_cast<__m128i*>(bin_k), bin);
  if (_mm_movemask_ps(_mm_cmpge_ps(uk, hi))) [[unlikely]] {
    // Beyond both (a cell over three or more bins): search the CDF from the cell's second bin on.
    alignas(16) float u_k[kLambdaCount], lo_k[kLambdaCount], hi_k[kLambdaCount];
    _mm_store_ps(u_k, uk);
    _mm_store_ps(lo_k, lo);
    _mm_store_ps(hi_k, hi);
    const int n = static_cast<int>(cdf_.size()) - 1;
    for (int k = 0; k < kLambdaCount; ++k) {
      if (!(u_k[k] >= hi_k[k])) continue;
      int i = cells_[index[k]].bin1 + 1;
      while (i + 1 < n && cdf_[i + 1] <= u_k[k]) ++i;
      bin_k[k] = i, lo_k[k] = cdf_[i], hi_k[k] = cdf_[i + 1];
    }
    lo = _mm_load_ps(lo_k);
    hi = _mm_load_ps(hi_k);
  }
  const __m128 mass = _mm_sub_ps(hi, lo);  // > 0: lo ≤ u_k < hi
  const __m128 du = _mm_min_ps(_mm_max_ps(_mm_setzero_ps(), _mm_div_ps(_mm_sub_ps(uk, lo), mass)), _mm_set1_ps(1.0f));
  // lo_nm + bin is a whole number of nm, exact in float; λ stays below the bin's upper edge, so
  // pdf(λ) finds this bin.
  const __m128 edge =
      _mm_add_ps(_mm_set1_ps(lo_nm_), _mm_cvtepi32_ps(_mm_load_si128(reinterpret_cast<__m128i*>(bin_k))));
  const __m128 below_next =
      _mm_castsi128_ps(_mm_sub_epi32(_mm_castps_si128(_mm_add_ps(edge, _mm_set1_ps(1.0f))), _mm_set1_epi32(1)));
  SampledWavelengths wl;
  // std::min(edge + du, below_next): below_next where it is less, as minps(below_next, x) gives.
  _mm_storeu_ps(&wl.lambda_nm[0], _mm_min_ps(below_next, _mm_add_ps(edge, du)));
  _mm_storeu_ps(&wl.pdf[0], mass);  // per nm: the bins are 1 nm wide
  return wl;
}

float WavelengthSampler::pdf(float lambda_nm) const {
  const int n = static_cast<int>(cdf_.size()) - 1;
  if (!(lambda_nm >= lo_nm_ && lambda_nm < lo_nm_ + static_cast<float>(n))) return 0.0f;
  const int bin = std::min(bin_of(lambda_nm), n - 1);
  return cdf_[bin + 1] - cdf_[bin];
}

}  // namespace sylva

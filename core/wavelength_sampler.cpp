// WavelengthSampler (core/band.h): the bands' groups, each group's CDF inversion, and the mixture
// density every lane is weighted by.
#include "core/band.h"
#include "core/simd.h"

#include <emmintrin.h>  // SSE2 only: the x86-64 baseline (docs/design.md §10, "Build cost")
#include <algorithm>
#include <limits>

namespace sylva {

namespace {

// The response-weighted mean wavelength of a band's importance.
double centre_nm(const Band& band) {
  double sum = 0, weight = 0;
  for (int i = 0; i < kLambdaSamples; ++i) {
    sum += static_cast<double>(band.importance[i]) * DenseSpectrum::grid_lambda(i);
    weight += band.importance[i];
  }
  return weight > 0 ? sum / weight : 0.0;
}

// The bands' groups, at most kLambdaBlocks: one band each while they fit, else the two groups
// nearest in centre wavelength merged until they do. Groups are ordered by their first band.
std::vector<std::vector<size_t>> band_groups(const std::vector<Band>& bands) {
  std::vector<std::vector<size_t>> groups;
  std::vector<double> centre;
  for (size_t b = 0; b < bands.size(); ++b) {
    groups.push_back({b});
    centre.push_back(centre_nm(bands[b]));
  }
  const auto group_centre = [&](const std::vector<size_t>& g) {
    double c = 0;
    for (const size_t b : g) c += centre[b];
    return c / static_cast<double>(g.size());
  };
  while (groups.size() > static_cast<size_t>(kLambdaBlocks)) {
    size_t best_a = 0, best_b = 1;
    double best = std::numeric_limits<double>::infinity();
    for (size_t a = 0; a < groups.size(); ++a)
      for (size_t b = a + 1; b < groups.size(); ++b) {
        const double d = std::abs(group_centre(groups[a]) - group_centre(groups[b]));
        if (d < best) best = d, best_a = a, best_b = b;
      }
    groups[best_a].insert(groups[best_a].end(), groups[best_b].begin(), groups[best_b].end());
    std::sort(groups[best_a].begin(), groups[best_a].end());
    groups.erase(groups.begin() + static_cast<std::ptrdiff_t>(best_b));
  }
  return groups;
}

}  // namespace

WavelengthSampler::Inversion::Inversion(std::vector<float> w) {
  // The table spans the 1 nm bins from the first to the last with importance: the same density in a
  // table a third the size for the rgb and nir bands.
  const auto first = std::find_if(w.begin(), w.end(), [](float x) { return x > 0; });
  if (first != w.end()) {
    const auto last = std::find_if(w.rbegin(), w.rend(), [](float x) { return x > 0; }).base();
    lo_nm = kLambdaMin + static_cast<float>(first - w.begin());
    w = std::vector<float>(first, last);
  }
  const int n = static_cast<int>(w.size());
  std::vector<DistributionBin> table(n + 1);
  std::vector<uint32_t> guide(n);
  Distribution1D::tabulate(w.data(), n, table.data(), guide.data());
  cdf.resize(n + 1);
  for (int i = 0; i <= n; ++i) cdf[i] = table[i].cdf;
  // Each cell's first bin: the bin with mass whose [cdf, next cdf) holds the cell's start.
  const auto next_with_mass = [&](int i) {
    while (i < n && !(cdf[i + 1] > cdf[i])) ++i;
    return i;  // n: none
  };
  cells.resize(kCells);
  int bin = next_with_mass(0);
  for (int k = 0; k < kCells; ++k) {
    const float u0 = static_cast<float>(k) / kCells;
    while (bin + 1 < n && cdf[bin + 1] <= u0) bin = next_with_mass(bin + 1);
    const int second = next_with_mass(bin + 1);
    cells[k] = Cell{cdf[bin], second < n ? cdf[second] : 1.0f, second < n ? cdf[second + 1] : 1.0f,
                    static_cast<uint16_t>(bin), static_cast<uint16_t>(second < n ? second : bin)};
  }
}

glm::vec4 WavelengthSampler::Inversion::sample4(const float* u) const {
  // Four wavelengths side by side in one SSE register each step (bench/README.md, "Four at a
  // time"): the same operations as one wavelength at a time, so the same bits.
  const __m128 uk = _mm_loadu_ps(u);
  // Each u_k's cell (u_k < 1, so the index stays below kCells), loaded together so the misses
  // overlap, then transposed: cdf0, cdf1, end1 and the two bins of each wavelength's cell.
  alignas(16) int32_t index[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(index), _mm_cvttps_epi32(_mm_mul_ps(uk, _mm_set1_ps(kCells))));
  __m128 cdf0 = _mm_loadu_ps(&cells[index[0]].cdf0);
  __m128 cdf1 = _mm_loadu_ps(&cells[index[1]].cdf0);
  __m128 end1 = _mm_loadu_ps(&cells[index[2]].cdf0);
  __m128 bins = _mm_loadu_ps(&cells[index[3]].cdf0);
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
  alignas(16) int32_t bin_k[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(bin_k), bin);
  if (_mm_movemask_ps(_mm_cmpge_ps(uk, hi))) [[unlikely]] {
    // Beyond both (a cell over three or more bins): search the CDF from the cell's second bin on.
    alignas(16) float u_k[4], lo_k[4], hi_k[4];
    _mm_store_ps(u_k, uk);
    _mm_store_ps(lo_k, lo);
    _mm_store_ps(hi_k, hi);
    const int n = static_cast<int>(cdf.size()) - 1;
    for (int k = 0; k < 4; ++k) {
      if (!(u_k[k] >= hi_k[k])) continue;
      int i = cells[index[k]].bin1 + 1;
      while (i + 1 < n && cdf[i + 1] <= u_k[k]) ++i;
      bin_k[k] = i, lo_k[k] = cdf[i], hi_k[k] = cdf[i + 1];
    }
    lo = _mm_load_ps(lo_k);
    hi = _mm_load_ps(hi_k);
  }
  const __m128 mass = _mm_sub_ps(hi, lo);  // > 0: lo ≤ u_k < hi
  const __m128 du = _mm_min_ps(_mm_max_ps(_mm_setzero_ps(), _mm_div_ps(_mm_sub_ps(uk, lo), mass)), _mm_set1_ps(1.0f));
  // lo_nm + bin is a whole number of nm, exact in float; λ stays below the bin's upper edge, so
  // pdf(λ) finds this bin.
  const __m128 edge =
      _mm_add_ps(_mm_set1_ps(lo_nm), _mm_cvtepi32_ps(_mm_load_si128(reinterpret_cast<__m128i*>(bin_k))));
  const __m128 below_next =
      _mm_castsi128_ps(_mm_sub_epi32(_mm_castps_si128(_mm_add_ps(edge, _mm_set1_ps(1.0f))), _mm_set1_epi32(1)));
  // std::min(edge + du, below_next): below_next where it is less, as minps(below_next, x) gives.
  glm::vec4 lambda;
  _mm_storeu_ps(&lambda[0], _mm_min_ps(below_next, _mm_add_ps(edge, du)));
  return lambda;
}

WavelengthSampler::WavelengthSampler(const std::vector<Band>& bands) {
  std::vector<std::vector<size_t>> groups = band_groups(bands);
  if (groups.empty()) groups.emplace_back();  // no band: one group of no importance (uniform)
  const int g_count = static_cast<int>(groups.size());
  band_group_.assign(bands.size(), 0);
  for (int g = 0; g < g_count; ++g)
    for (const size_t b : groups[static_cast<size_t>(g)]) band_group_[b] = g;
  for (const auto& group : groups) {
    std::vector<float> w(kLambdaSamples - 1, 0.0f);
    for (const size_t b : group)
      for (int i = 0; i + 1 < kLambdaSamples; ++i) w[i] += 0.5f * (bands[b].importance[i] + bands[b].importance[i + 1]);
    groups_.emplace_back(std::move(w));
  }
  // Blocks: kLambdaBlocks / G each, one more for each of the first kLambdaBlocks mod G groups.
  group_blocks_.assign(static_cast<size_t>(g_count), kLambdaBlocks / g_count);
  for (int g = 0; g < kLambdaBlocks % g_count; ++g) ++group_blocks_[static_cast<size_t>(g)];
  for (int g = 0; g < g_count; ++g)
    for (int r = 0; r < group_blocks_[static_cast<size_t>(g)]; ++r) {
      block_group_.push_back(g);
      block_rank_.push_back(r);
    }
  // q(λ) = Σ_g (n_g / n) p_g(λ) on the 1 nm bins from the lowest group's first bin to the highest's last.
  lo_nm_ = kLambdaMax;
  float hi_nm = kLambdaMin;
  for (const Inversion& inv : groups_) {
    lo_nm_ = std::min(lo_nm_, inv.lo_nm);
    hi_nm = std::max(hi_nm, inv.lo_nm + static_cast<float>(inv.cdf.size() - 1));
  }
  pdf_.assign(static_cast<size_t>(hi_nm - lo_nm_), 0.0f);
  for (int g = 0; g < g_count; ++g) {
    const Inversion& inv = groups_[static_cast<size_t>(g)];
    const float share = static_cast<float>(group_blocks_[static_cast<size_t>(g)]) / kLambdaBlocks;
    const int offset = bin_of(inv.lo_nm);
    for (int i = 0; i + 1 < static_cast<int>(inv.cdf.size()); ++i)
      pdf_[static_cast<size_t>(offset + i)] += share * inv.mass(i);
  }
}

SampledWavelengths WavelengthSampler::sample(float u, float u_hero) const {
  SampledWavelengths wl;
  wl.hero = std::min(static_cast<int>(u_hero * kLambdaCount), kLambdaCount - 1);
  const int n = static_cast<int>(pdf_.size());
  for (int b = 0; b < kLambdaBlocks; ++b) {
    const int g = block_group_[static_cast<size_t>(b)];
    // The group's lanes i = 0 .. 4·blocks − 1 at u_i = u + i / (4·blocks), wrapped into [0, 1).
    const float lanes = 4.0f * static_cast<float>(group_blocks_[static_cast<size_t>(g)]);
    alignas(16) float uk[4];
    for (int k = 0; k < 4; ++k) {
      const float v = u + static_cast<float>(4 * block_rank_[static_cast<size_t>(b)] + k) / lanes;
      uk[k] = v >= 1.0f ? v - 1.0f : v;
    }
    wl.lambda_nm.block(b) = groups_[static_cast<size_t>(g)].sample4(uk);
    for (int k = 0; k < 4; ++k)
      wl.pdf[4 * b + k] = pdf_[static_cast<size_t>(std::clamp(bin_of(wl.lambda_nm[4 * b + k]), 0, n - 1))];
  }
  return wl;
}

float WavelengthSampler::pdf(float lambda_nm) const {
  const int n = static_cast<int>(pdf_.size());
  if (!(lambda_nm >= lo_nm_ && lambda_nm < lo_nm_ + static_cast<float>(n))) return 0.0f;
  return pdf_[static_cast<size_t>(std::min(bin_of(lambda_nm), n - 1))];
}

}  // namespace sylva

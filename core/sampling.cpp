#include "core/sampling.h"

#include "core/fast_math.h"

#include <numeric>

namespace sylva {

float Distribution1D::tabulate(const float* weights, int n, DistributionBin* bins, uint32_t* guide) {
  double acc = 0;
  std::vector<double> cdf(n + 1, 0.0);
  for (int i = 0; i < n; ++i) {
    acc += std::max(0.0f, weights[i]);
    cdf[i + 1] = acc;
  }
  const float integral = n > 0 ? static_cast<float>(acc / n) : 0.0f;
  for (int i = 0; i <= n; ++i) {
    bins[i].cdf = acc > 0 ? static_cast<float>(cdf[i] / acc) : static_cast<float>(i) / std::max(1, n);
    bins[i].pdf = i == n ? 0.0f : integral > 0 ? std::max(0.0f, weights[i]) / integral : 1.0f;
  }
  if (n > 0) bins[n].cdf = 1.0f;
  for (int k = 0, i = 0; k < n; ++k) {
    const float x = static_cast<float>(k) / static_cast<float>(n);
    while (i + 1 < n && bins[i + 1].cdf <= x) ++i;
    guide[k] = static_cast<uint32_t>(i);
  }
  return integral;
}

Distribution1D::Distribution1D(const std::vector<float>& weights) : bins_(weights.size() + 1), guide_(weights.size()) {
  integral_ = tabulate(weights.data(), static_cast<int>(weights.size()), bins_.data(), guide_.data());
}

Distribution2D::Distribution2D(const std::vector<float>& weights, int nu, int nv)
    : nu_(nu),
      row_bins_(static_cast<size_t>(nu + 1) * static_cast<size_t>(nv)),
      row_guides_(static_cast<size_t>(nu) * static_cast<size_t>(nv)) {
  std::vector<float> row_mass(nv);
  for (int v = 0; v < nv; ++v)
    row_mass[v] = Distribution1D::tabulate(weights.data() + static_cast<size_t>(v) * nu, nu, row_bins(v), row_guide(v));
  marginal_ = Distribution1D(row_mass);
  pdf_.resize(static_cast<size_t>(nu) * static_cast<size_t>(nv));
  for (int v = 0; v < nv; ++v)
    for (int u = 0; u < nu; ++u) pdf_[static_cast<size_t>(v) * nu + u] = marginal_.bin_pdf(v) * row_bins(v)[u].pdf;
}

Vec2 Distribution2D::sample(Vec2 u, float* pdf) const {
  float pdf_v = 0, pdf_u = 0;
  int row = 0;
  const float v = marginal_.sample(u.y, &pdf_v, &row);
  const float uu = sample_bins(row_bins(row), row_guide(row), nu_, u.x, &pdf_u, nullptr);
  if (pdf) *pdf = pdf_v * pdf_u;
  return {uu, v};
}

float Distribution2D::pdf(Vec2 p) const {
  return pdf_[static_cast<size_t>(marginal_.bin_of(p.y)) * nu_ + bin_index(p.x, nu_)];
}

}  // namespace sylva

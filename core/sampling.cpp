#include "core/sampling.h"

#include <numeric>

namespace sylva {

Vec2 sample_uniform_disk(Vec2 u) {
  const Vec2 o = 2.0f * u - Vec2(1.0f);
  if (o.x == 0 && o.y == 0) return Vec2(0.0f);
  float r, theta;
  if (std::abs(o.x) > std::abs(o.y)) {
    r = o.x;
    theta = (kPi / 4) * (o.y / o.x);
  } else {
    r = o.y;
    theta = kPi / 2 - (kPi / 4) * (o.x / o.y);
  }
  return r * Vec2(std::cos(theta), std::sin(theta));
}

Distribution1D::Distribution1D(std::vector<float> weights) : weights_(std::move(weights)) {
  const int n = size();
  cdf_.assign(n + 1, 0.0f);
  double acc = 0;
  std::vector<double> cdf(n + 1, 0.0);
  for (int i = 0; i < n; ++i) {
    acc += std::max(0.0f, weights_[i]);
    cdf[i + 1] = acc;
  }
  integral_ = n > 0 ? static_cast<float>(acc / n) : 0.0f;
  for (int i = 0; i <= n; ++i)
    cdf_[i] = acc > 0 ? static_cast<float>(cdf[i] / acc) : static_cast<float>(i) / std::max(1, n);
  if (n > 0) cdf_[n] = 1.0f;
  guide_.resize(n);
  for (int k = 0, i = 0; k < n; ++k) {
    const float x = static_cast<float>(k) / static_cast<float>(n);
    while (i + 1 < n && cdf_[i + 1] <= x) ++i;
    guide_[k] = i;
  }
}

float Distribution1D::sample(float u, float* pdf, int* bin) const {
  const int n = size();
  // Last bin whose cdf start is <= u (found from the guide table: O(1) on average), then back over
  // bins with no mass.
  int i = guide_[std::clamp(static_cast<int>(u * static_cast<float>(n)), 0, n - 1)];
  while (i > 0 && cdf_[i] > u) --i;
  while (i + 1 < n && cdf_[i + 1] <= u) ++i;
  while (i > 0 && cdf_[i + 1] == cdf_[i]) --i;
  const float width = cdf_[i + 1] - cdf_[i];
  const float du = width > 0 ? (u - cdf_[i]) / width : 0.5f;
  if (pdf) *pdf = integral_ > 0 ? std::max(0.0f, weights_[i]) / integral_ : 1.0f;
  if (bin) *bin = i;
  return std::min((static_cast<float>(i) + std::clamp(du, 0.0f, 1.0f)) / static_cast<float>(n), 0x1.fffffep-1f);
}

Distribution2D::Distribution2D(const std::vector<float>& weights, int nu, int nv) {
  conditional_.reserve(nv);
  std::vector<float> row_mass(nv);
  for (int v = 0; v < nv; ++v) {
    conditional_.emplace_back(std::vector<float>(weights.begin() + v * nu, weights.begin() + (v + 1) * nu));
    row_mass[v] = conditional_.back().integral();
  }
  marginal_ = Distribution1D(std::move(row_mass));
  nu_ = nu;
  pdf_.resize(static_cast<size_t>(nu) * static_cast<size_t>(nv));
  for (int v = 0; v < nv; ++v)
    for (int u = 0; u < nu; ++u)
      pdf_[static_cast<size_t>(v) * nu + u] = marginal_.bin_pdf(v) * conditional_[v].bin_pdf(u);
}

Vec2 Distribution2D::sample(Vec2 u, float* pdf) const {
  float pdf_v = 0, pdf_u = 0;
  int row = 0;
  const float v = marginal_.sample(u.y, &pdf_v, &row);
  const float uu = conditional_[row].sample(u.x, &pdf_u);
  if (pdf) *pdf = pdf_v * pdf_u;
  return {uu, v};
}

float Distribution2D::pdf(Vec2 p) const {
  const int row = marginal_.bin_of(p.y);
  return pdf_[static_cast<size_t>(row) * nu_ + conditional_[row].bin_of(p.x)];
}

}  // namespace sylva

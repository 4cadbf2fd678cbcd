#include "render/materials/material.h"

#include "render/materials/material_checks.h"

#include "core/error.h"
#include "core/registry.h"
#include "core/sampling.h"

#include <fmt/core.h>

namespace sylva {

void check_unit_range(const std::string& name, const char* what, const DenseSpectrum& s) {
  if (s.min_value() < 0.0f || s.max_value() > 1.0f)
    throw Error(fmt::format("material '{}': {} must lie in [0, 1] (found {:.4g} .. {:.4g})", name, what, s.min_value(),
                            s.max_value()));
}

void check_energy(const std::string& name, const DenseSpectrum& r, const DenseSpectrum& t, const char* face) {
  for (int i = 0; i < kLambdaSamples; ++i)
    if (r[i] + t[i] > 1.0f + 1e-4f)
      throw Error(fmt::format("material '{}': reflectance + transmittance = {:.4f} > 1 at {} nm ({} face)", name,
                              r[i] + t[i], DenseSpectrum::grid_lambda(i), face));
}

Material create_material(const std::string& name, const Params& params) {
  const std::string type = params.string("type", "diffuse");
  std::optional<Material> m = create_registered<Material>(type, name, params);
  if (!m) params.fail(fmt::format("material type must be one of {}, not \"{}\"", registered_names<Material>(), type));
  params.check_unused();
  return std::move(*m);
}

MaterialLobes::MaterialLobes(const std::vector<Material>& materials)
    : table_(2 * materials.size() * static_cast<size_t>(kLambdaSamples)) {
  // Each material's lobes at the grid wavelengths themselves, four at a time: there the lerp's
  // fraction is 0, so these are the spectra's grid values exactly (but for the last, 2500 nm,
  // which DenseSpectrum::eval reaches as v[n−2] + 1·(v[n−1] − v[n−2]): at most an ulp apart).
  for (size_t m = 0; m < materials.size(); ++m)
    for (int i = 0; i < kLambdaSamples; i += kLambdaCount) {
      SampledWavelengths wl;
      for (int k = 0; k < kLambdaCount; ++k)
        wl.lambda_nm[k] = DenseSpectrum::grid_lambda(std::min(i + k, kLambdaSamples - 1));
      SampledSpectrum rf(0.0f), tf(0.0f), rb(0.0f), tb(0.0f);
      std::visit(
          [&](const auto& material) {
            material.lobes(wl, true, rf, tf);
            material.lobes(wl, false, rb, tb);
          },
          materials[m]);
      for (int k = 0; k < kLambdaCount && i + k < kLambdaSamples; ++k) {
        table_[2 * m * kLambdaSamples + static_cast<size_t>(i + k)] = {rf[k], tf[k]};
        table_[(2 * m + 1) * kLambdaSamples + static_cast<size_t>(i + k)] = {rb[k], tb[k]};
      }
    }
}

void MaterialLobes::lobes(uint32_t material, const SampledWavelengths& wl, bool front, SampledSpectrum& reflect,
                          SampledSpectrum& transmit) const {
  const GridLobes* grid = &table_[(2 * static_cast<size_t>(material) + (front ? 0 : 1)) * kLambdaSamples];
  const GridPositions g = grid_positions(wl);
  const GridLobes* a[kLambdaCount];
  for (int k = 0; k < kLambdaCount; ++k) a[k] = grid + g.index[k];
  // DenseSpectrum::eval's lerp, four wavelengths at a time.
  const SampledSpectrum r0(a[0][0].reflect, a[1][0].reflect, a[2][0].reflect, a[3][0].reflect);
  const SampledSpectrum r1(a[0][1].reflect, a[1][1].reflect, a[2][1].reflect, a[3][1].reflect);
  const SampledSpectrum t0(a[0][0].transmit, a[1][0].transmit, a[2][0].transmit, a[3][0].transmit);
  const SampledSpectrum t1(a[0][1].transmit, a[1][1].transmit, a[2][1].transmit, a[3][1].transmit);
  reflect = r0 + g.fraction * (r1 - r0);
  transmit = t0 + g.fraction * (t1 - t0);
}

Bsdf::Bsdf(const Material& material, const SampledWavelengths& wl, bool front) {
  std::visit([&](const auto& m) { m.lobes(wl, front, reflect_, transmit_); }, material);
  select_lobes();
}

Bsdf::Bsdf(const MaterialLobes& table, uint32_t material, const SampledWavelengths& wl, bool front) {
  table.lobes(material, wl, front, reflect_, transmit_);
  select_lobes();
}

void Bsdf::select_lobes() {
  const float r = average(reflect_), t = average(transmit_);
  p_reflect_ = (r + t) > 0 ? r / (r + t) : 1.0f;
}

SampledSpectrum Bsdf::eval(const Vec3& wo, const Vec3& wi) const {
  const bool same_side = (wo.z > 0) == (wi.z > 0);
  return (same_side ? reflect_ : transmit_) * kInvPi;
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
  const bool same_side = (wo.z > 0) == (wi.z > 0);
  return (same_side ? p_reflect_ : 1.0f - p_reflect_) * cosine_hemisphere_pdf(std::abs(wi.z));
}

bool Bsdf::sample(const Vec3& wo, Vec2 u, float u_lobe, BsdfSample* out) const {
  Vec3 wi = sample_cosine_hemisphere(u);
  if (wi.z <= 0) return false;
  const bool transmit = u_lobe >= p_reflect_;
  const float side = wo.z >= 0 ? 1.0f : -1.0f;
  wi.z *= transmit ? -side : side;
  const float lobe_p = transmit ? 1.0f - p_reflect_ : p_reflect_;
  if (lobe_p <= 0) return false;
  out->wi = wi;
  out->pdf = lobe_p * cosine_hemisphere_pdf(std::abs(wi.z));
  out->transmitted = transmit;
  out->value = (transmit ? transmit_ : reflect_) / lobe_p;  // f·cos/pdf = (ρ/π)·cos / (p·cos/π)
  return out->pdf > 0;
}

}  // namespace sylva

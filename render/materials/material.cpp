#include "render/materials/material.h"

#include "render/materials/material_checks.h"

#include "core/error.h"
#include "core/registry.h"
#include "core/sampling.h"

#include <fmt/core.h>

#include <type_traits>

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

Bsdf::Bsdf(const Material& material, const SampledWavelengths& wl, bool front) {
  std::visit([&](const auto& m) { m.lobes(wl, front, reflect_, transmit_); }, material);
  select_lobes();
}

Material scaled_reflectance(const Material& m, float factor) {
  Material out = m;
  std::visit(
      [factor](auto& mat) {
        if constexpr (std::is_same_v<std::decay_t<decltype(mat)>, DiffuseMaterial>) {
          mat.reflectance *= factor;
        } else {
          mat.reflectance_front *= factor;
          mat.reflectance_back *= factor;
        }
      },
      out);
  return out;
}

}  // namespace sylva

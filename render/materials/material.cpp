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

namespace {

// The material's emitted(ctx), or black for a material without one.
template <typename M>
SampledSpectrum emitted_of(const M& m, const HitContext& ctx) {
  if constexpr (requires { m.emitted(ctx); })
    return m.emitted(ctx);
  else
    return SampledSpectrum(0.0f);
}

}  // namespace

Bsdf material_bsdf(const Material& material, const HitContext& ctx) {
  Bsdf bsdf;
  std::visit([&](const auto& m) { m.add_lobes(ctx, bsdf); }, material);
  bsdf.finish();
  return bsdf;
}

bool emits(const Material& material) {
  return std::visit(
      [](const auto& m) {
        return requires(const HitContext& c) { m.emitted(c); };
      },
      material);
}

SampledSpectrum emitted_radiance(const Material& material, const HitContext& ctx) {
  return std::visit([&](const auto& m) { return emitted_of(m, ctx); }, material);
}

float emitted_power_w_m2(const Material& material) {
  return std::visit(
      [](const auto& m) {
        if constexpr (requires { m.emitted_power_w_m2(); })
          return m.emitted_power_w_m2();
        else
          return 0.0f;
      },
      material);
}

const DenseSpectrum& display_reflectance(const Material& material) {
  return std::visit([](const auto& m) -> const DenseSpectrum& { return m.display_reflectance(); }, material);
}

bool is_foliage(const Material& material) {
  return std::visit([](const auto& m) { return std::decay_t<decltype(m)>::kFoliage; }, material);
}

Material scaled_reflectance(const Material& m, float factor) {
  Material out = m;
  std::visit([factor](auto& mat) { mat.scale_reflectance(factor); }, out);
  return out;
}

MaterialLobes::MaterialLobes(const std::vector<Material>& materials)
    : materials_(&materials),
      layouts_(2 * materials.size()),
      table_(2 * materials.size() * static_cast<size_t>(kLambdaSamples)),
      emits_(materials.size()) {
  // Each material's lobes at the grid wavelengths themselves, four at a time: there the lerp's
  // fraction is 0, so these are the spectra's grid values exactly (but for the last, 2500 nm,
  // which DenseSpectrum::eval reaches as v[n−2] + 1·(v[n−1] − v[n−2]): at most an ulp apart).
  for (size_t m = 0; m < materials.size(); ++m) {
    emits_[m] = sylva::emits(materials[m]) ? 1 : 0;
    if (std::visit([](const auto& mat) { return mat.varies(); }, materials[m])) continue;
    for (size_t face = 2 * m; face < 2 * m + 2; ++face) {
      Layout layout;
      layout.tabulated = true;
      for (int i = 0; i < kLambdaSamples && layout.tabulated; i += kLambdaCount) {
        SampledWavelengths wl;
        for (int k = 0; k < kLambdaCount; ++k)
          wl.lambda_nm[k] = DenseSpectrum::grid_lambda(std::min(i + k, kLambdaSamples - 1));
        HitContext ctx;
        ctx.front = face == 2 * m;
        ctx.wl = &wl;
        const Bsdf bsdf = material_bsdf(materials[m], ctx);
        // Tabulated: at most kTabulatedLobes Lambertian lobes, the same kinds at every wavelength.
        if (i == 0 && bsdf.lobe_count() <= kTabulatedLobes) {
          layout.count = bsdf.lobe_count();
          for (int l = 0; l < layout.count; ++l)
            if (const auto* lobe = std::get_if<LambertLobe>(&bsdf.lobe(l)))
              layout.transmission[l] = lobe->transmission;
            else
              layout.tabulated = false;
        }
        if (bsdf.lobe_count() != layout.count) layout.tabulated = false;
        for (int l = 0; l < layout.count && layout.tabulated; ++l) {
          const auto* lobe = std::get_if<LambertLobe>(&bsdf.lobe(l));
          if (lobe == nullptr || lobe->transmission != layout.transmission[l]) {
            layout.tabulated = false;
            break;
          }
          for (int k = 0; k < kLambdaCount && i + k < kLambdaSamples; ++k)
            table_[face * kLambdaSamples + static_cast<size_t>(i + k)].albedo[l] = lobe->albedo[k];
        }
      }
      layouts_[face] = layout;
    }
  }
}

}  // namespace sylva

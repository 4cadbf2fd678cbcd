#include "render/materials/emissive.h"

#include "core/error.h"
#include "render/materials/material_checks.h"

#include <fmt/core.h>

namespace sylva {

EmissiveMaterial make_emissive(const std::string& name, const DenseSpectrum& radiance, const DenseSpectrum& reflectance,
                               bool two_sided) {
  if (radiance.min_value() < 0.0f)
    throw Error(fmt::format("material '{}': radiance must not be negative (found {:.4g})", name, radiance.min_value()));
  check_unit_range(name, "reflectance", reflectance);
  return EmissiveMaterial{{radiance}, {reflectance}, two_sided};
}

EmissiveMaterial EmissiveMaterial::create(const std::string& name, const Params& params) {
  if (!params.has("radiance")) params.fail("emissive material '" + name + "' needs a radiance spectrum");
  const DenseSpectrum radiance = params.spectrum("radiance", Extrapolate::Clamp);
  if (radiance.min_value() < 0.0f)
    params.fail("radiance", fmt::format("radiance must not be negative (found {:.4g})", radiance.min_value()));
  const std::optional<DenseSpectrum> reflectance = params.optional_spectrum("reflectance", Extrapolate::Clamp);
  if (reflectance && (reflectance->min_value() < 0.0f || reflectance->max_value() > 1.0f))
    params.fail("reflectance", fmt::format("reflectance must lie in [0, 1] (found {:.4g} .. {:.4g})",
                                           reflectance->min_value(), reflectance->max_value()));
  return make_emissive(name, radiance, reflectance ? *reflectance : DenseSpectrum::constant(0.0f),
                       params.boolean("two_sided", false));
}

}  // namespace sylva

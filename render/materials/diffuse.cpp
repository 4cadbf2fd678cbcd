#include "render/materials/diffuse.h"

#include "core/error.h"

#include "render/materials/material_checks.h"

namespace sylva {

DiffuseMaterial make_diffuse(const std::string& name, const DenseSpectrum& reflectance) {
  check_unit_range(name, "reflectance", reflectance);
  return DiffuseMaterial{reflectance};
}

DiffuseMaterial DiffuseMaterial::create(const std::string& name, const Params& params) {
  if (!params.has("reflectance")) params.fail("diffuse material '" + name + "' needs a reflectance");
  const DenseSpectrum reflectance = params.spectrum("reflectance", Extrapolate::Clamp);
  try {
    return make_diffuse(name, reflectance);
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    params.fail(e.what());
  }
}

void DiffuseMaterial::lobes(const SampledWavelengths& wl, bool, SampledSpectrum& reflect, SampledSpectrum&) const {
  reflect = reflectance.eval(wl);
}

}  // namespace sylva

#include "render/materials/diffuse.h"

#include "core/error.h"
#include "core/rgb_spectrum.h"

#include "render/materials/material_checks.h"

namespace sylva {

DiffuseMaterial make_diffuse(const std::string& name, const DenseSpectrum& reflectance) {
  check_unit_range(name, "reflectance", reflectance);
  return DiffuseMaterial{{reflectance}};
}

DiffuseMaterial DiffuseMaterial::create(const std::string& name, const Params& params) {
  if (params.has("reflectance") == params.has("rgb"))
    params.fail("diffuse material '" + name + "' needs a reflectance spectrum or an rgb colour (not both)");
  DenseSpectrum reflectance;
  if (params.has("rgb")) {
    // An artist's colour, linear Rec.709/sRGB primaries (D65), up-sampled to a smooth spectrum (Smits 1999).
    const Vec3 rgb = params.vec3("rgb", Vec3(0.0f));
    for (int c = 0; c < 3; ++c)
      if (!(rgb[c] >= 0.0f && rgb[c] <= 1.0f)) params.fail("rgb", "rgb components must lie in [0, 1] (linear)");
    reflectance = rgb_to_reflectance(rgb);
  } else {
    reflectance = params.spectrum("reflectance", Extrapolate::Clamp);
  }
  try {
    return make_diffuse(name, reflectance);
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    params.fail(e.what());
  }
}

}  // namespace sylva

#pragma once
// Lambertian material: diffuse reflectance ρ(λ), no transmission.
//
// Scene file: [materials.NAME] type = "diffuse", reflectance = SPECTRUM.

#include "core/params.h"
#include "core/spectrum.h"

#include <string>
#include <string_view>

namespace sylva {

struct DiffuseMaterial {
  static constexpr std::string_view kType = "diffuse";
  static constexpr bool kFoliage = false;  // the flux budget counts it as bark or ground

  DenseSpectrum reflectance;

  // Reads `reflectance`, or `rgb` (linear sRGB, Smits up-sampling); throws ParseError for a missing or
  // unphysical spectrum.
  static DiffuseMaterial create(const std::string& name, const Params& params);
  // The reflected and transmitted spectra at the carried wavelengths.
  void lobes(const SampledWavelengths& wl, bool front, SampledSpectrum& reflect, SampledSpectrum& transmit) const;
  const DenseSpectrum& display_reflectance() const { return reflectance; }
};

// Throws sylva::Error (naming `name`) if the reflectance leaves [0, 1].
DiffuseMaterial make_diffuse(const std::string& name, const DenseSpectrum& reflectance);

}  // namespace sylva

#pragma once
// Bi-Lambertian leaf: reflects ρ(λ) and transmits τ(λ) diffusely, optionally with different spectra
// on the back (abaxial) face; ρ + τ ≤ 1 is checked when the material is made.
//
// Scene file: [materials.NAME] type = "leaf", then either prospect = { N, Cab, Car, Ant, Cbrown, Cw,
// Cm } (PROSPECT-D, core/prospect.h) or reflectance = SPECTRUM, transmittance = SPECTRUM and
// optionally back_reflectance, back_transmittance.

#include "core/params.h"
#include "core/spectrum.h"

#include <string>
#include <string_view>

namespace sylva {

struct LeafMaterial {
  static constexpr std::string_view kType = "leaf";
  static constexpr bool kFoliage = true;  // the flux budget counts its absorption as the leaves'

  DenseSpectrum reflectance_front, transmittance_front;
  DenseSpectrum reflectance_back, transmittance_back;

  static LeafMaterial create(const std::string& name, const Params& params);
  // Light arriving at the back face sees the back spectra; transmission is reciprocal.
  void lobes(const SampledWavelengths& wl, bool front, SampledSpectrum& reflect, SampledSpectrum& transmit) const;
  const DenseSpectrum& display_reflectance() const { return reflectance_front; }
};

// Throw sylva::Error (naming `name`) if any value is outside [0,1] or ρ + τ > 1 anywhere.
LeafMaterial make_leaf(const std::string& name, const DenseSpectrum& reflectance, const DenseSpectrum& transmittance);
LeafMaterial make_leaf(const std::string& name, const DenseSpectrum& reflectance_front,
                       const DenseSpectrum& transmittance_front, const DenseSpectrum& reflectance_back,
                       const DenseSpectrum& transmittance_back);

}  // namespace sylva

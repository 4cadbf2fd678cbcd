#pragma once
// A uniform sky: the same radiance from every direction of the sphere (furnace tests). Scene file:
// [sky] model = "uniform"; its spectrum is the radiance, W·m⁻²·sr⁻¹·nm⁻¹ (default 1).

#include "core/math.h"
#include "core/params.h"
#include "core/spectrum.h"

#include <string_view>

namespace sylva {

struct UniformSky {
  static constexpr std::string_view kType = "uniform";
  static constexpr bool kNormalisedToHorizontal = false;  // the spectrum is the radiance itself
  static constexpr bool kUpperHemisphereOnly = false;

  static UniformSky create(const Params&) { return {}; }
  DenseSpectrum default_spectrum() const { return DenseSpectrum::constant(1.0f); }
  float relative_radiance(const Vec3&, const Vec3&) const { return 1.0f; }
};

}  // namespace sylva

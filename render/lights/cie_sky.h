#pragma once
// The CIE standard general sky (ISO 15469 / CIE S 011): 15 relative luminance distributions; the
// sky spectrum is the diffuse irradiance on a horizontal surface and the radiance is that spectrum
// times the distribution, normalised to match it. Scene file: [sky] model = "cie", type = 1..15.

#include "core/math.h"
#include "core/params.h"
#include "core/spectrum.h"

#include <string_view>

namespace sylva {

// CIE relative sky luminance L(ω)/L(zenith) (ISO 15469 / CIE S 011), 0 below the horizon.
float cie_sky_relative_luminance(int type, const Vec3& dir, const Vec3& sun_dir);

struct CieSky {
  static constexpr std::string_view kType = "cie";
  // The spectrum is the horizontal diffuse irradiance (W·m⁻²·nm⁻¹), not a radiance.
  static constexpr bool kNormalisedToHorizontal = true;
  static constexpr bool kUpperHemisphereOnly = true;  // so a ground below the horizon may be added

  int type = 12;  // CIE standard general sky type 1–15 (12: clear, low turbidity)

  static CieSky create(const Params& params);
  DenseSpectrum default_spectrum() const { return astm_g173_diffuse(); }
  // The directional shape g(ω), relative to the zenith.
  float relative_radiance(const Vec3& dir, const Vec3& sun_dir) const {
    return cie_sky_relative_luminance(type, dir, sun_dir);
  }
};

}  // namespace sylva

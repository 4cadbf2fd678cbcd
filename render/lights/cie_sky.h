#pragma once
// The CIE standard general sky (ISO 15469 / CIE S 011): 15 relative luminance distributions; the
// sky spectrum is the diffuse irradiance on a horizontal surface and the radiance is that spectrum
// times the distribution, normalised to match it. Scene file: [sky] model = "cie", type = 1..15.

#include "core/fast_math.h"
#include "core/math.h"
#include "core/params.h"
#include "core/spectrum.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

namespace sylva {

// The CIE relative sky luminance L(ω)/L(zenith) for one sun direction (ISO 15469 / CIE S 011):
// gradation φ(Z) = 1 + a·exp(b / cos Z), indicatrix f(χ) = 1 + c·[exp(dχ) − exp(dπ/2)] + e·cos²χ,
// L(ω)/L(zenith) = f(χ)·φ(Z) / (f(Z_sun)·φ(0)); 0 below the horizon. What depends on the sun only
// is computed once.
class CieSkyShape {
 public:
  CieSkyShape(int type, const Vec3& sun_dir);
  float operator()(const Vec3& dir) const;
  const Vec3& sun_direction() const { return sun_dir_; }

 private:
  float gradation(float cos_z) const { return 1.0f + a_ * exp_fast(b_ / std::max(cos_z, 1e-4f)); }
  // χ, the angle to the sun, and its cosine (the dot product the caller has: no cos(acos(x))).
  float indicatrix(float chi, float cos_chi) const {
    return 1.0f + c_ * (exp_fast(d_ * chi) - exp_d_half_pi_) + e_ * sqr(cos_chi);
  }

  Vec3 sun_dir_;
  float a_, b_, c_, d_, e_;
  float exp_d_half_pi_;
  float inv_zenith_;  // 1 / (f(Z_sun)·φ(0))
};

// The same for one direction (a CieSkyShape made and used once).
float cie_sky_relative_luminance(int type, const Vec3& dir, const Vec3& sun_dir);

struct CieSky {
  static constexpr std::string_view kType = "cie";
  // The spectrum is the horizontal diffuse irradiance (W·m⁻²·nm⁻¹), not a radiance.
  static constexpr bool kNormalisedToHorizontal = true;
  static constexpr bool kUpperHemisphereOnly = true;  // so a ground below the horizon may be added

  int type = 12;  // CIE standard general sky type 1–15 (12: clear, low turbidity)

  static CieSky create(const Params& params);
  DenseSpectrum default_spectrum() const { return astm_g173_diffuse(); }
  // Computes the shape for this sun once (Environment does, for the scene's sun).
  void prepare(const Vec3& sun_dir);
  // The directional shape g(ω), relative to the zenith.
  float relative_radiance(const Vec3& dir, const Vec3& sun_dir) const;

 private:
  std::optional<CieSkyShape> shape_;
};

}  // namespace sylva

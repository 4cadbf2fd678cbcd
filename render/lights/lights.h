#pragma once
// Sun and sky: the scene's distant light, sampled as one mixture so next-event estimation and BSDF
// sampling combine with multiple importance sampling.
//
// Directions: world Z up, +Y north, +X east. Sun azimuth is the compass bearing (degrees clockwise
// from north), elevation the angle above the horizon.

#include "core/math.h"
#include "core/sampling.h"
#include "core/spectrum.h"
#include "render/lights/cie_sky.h"
#include "render/lights/preetham_sky.h"
#include "render/lights/uniform_sky.h"

#include <array>
#include <variant>
#include <vector>

namespace sylva {

Vec3 sun_direction(float azimuth_deg, float elevation_deg);

struct SunDesc {
  bool enabled = true;
  float azimuth_deg = 135.0f;
  float elevation_deg = 45.0f;
  float angular_radius_deg = 0.2665f;  // the solar disc seen from Earth
  // Spectral irradiance on a surface facing the sun, W·m⁻²·nm⁻¹ (default ASTM G173 direct+circumsolar).
  DenseSpectrum irradiance = astm_g173_direct();
};

// Sky models: a closed set open to extension. Each lives in its own header and provides
//   static constexpr std::string_view kType;           // [sky] model = "..."
//   static constexpr bool kNormalisedToHorizontal;     // spectrum = horizontal irradiance (else radiance)
//   static constexpr bool kUpperHemisphereOnly;        // zero below the horizon
//   static M create(const Params&);                     // reads its own parameters
//   DenseSpectrum default_spectrum() const;
//   float relative_radiance(dir, sun_dir) const;        // the directional shape g(ω)
// A spectral model (its colour varies over the dome) also provides
//   Vec3 basis_weights(dir, sun_dir) const;             // radiance = Σ w_i · basis()[i](λ)
//   std::array<DenseSpectrum, 3> basis() const;
//   bool own_spectrum;                                   // keep its own spectral shape (else match `spectrum`)
// and is sampled by its relative_radiance (luminance) map, evaluated spectrally.
// Adding a sky = its header + one entry in the variant below.
using SkyModel = std::variant<CieSky, UniformSky, PreethamSky>;

template <class M>
concept SpectralSkyModel = requires(const M& m, const Vec3& d) {
  { m.basis_weights(d, d) } -> std::same_as<Vec3>;
  m.basis();
};

inline bool normalised_to_horizontal(const SkyModel& m) {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::kNormalisedToHorizontal; }, m);
}
inline bool upper_hemisphere_only(const SkyModel& m) {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::kUpperHemisphereOnly; }, m);
}

struct SkyDesc {
  bool enabled = true;
  SkyModel model = CieSky{};
  // Normalised models (CIE, Preetham): the diffuse irradiance on a horizontal surface, W·m⁻²·nm⁻¹;
  // the sky's radiance is this spectrum times the relative distribution, normalised to match it
  // (Preetham: per wavelength, or in total when it keeps its own spectrum; preetham_sky.h).
  // Others (uniform): the radiance itself (W·m⁻²·sr⁻¹·nm⁻¹) in every direction.
  DenseSpectrum spectrum = astm_g173_diffuse();
  // Upper-hemisphere models only: below the horizon, a Lambertian ground of this albedo lit by the
  // sun and this sky (a stand-in for terrain beyond the scene's geometry). 0: black below the horizon.
  float ground_albedo = 0.0f;
  Vec3 sun_direction{0, 0, 1};  // for the CIE indicatrix
};

struct LightSample {
  Vec3 wi;  // world direction towards the light
  SampledSpectrum radiance;
  float pdf = 0;  // solid angle, of the whole mixture
};

class Environment {
 public:
  Environment() = default;
  Environment(const SunDesc& sun, const SkyDesc& sky);

  // Radiance arriving from world direction `dir`: the sun's within its disc, else the sky's. The
  // disc hides the sky: the sun's spectrum (ASTM G173 direct + circumsolar) already holds the
  // light scattered towards the viewer around it (docs/radiometry.md, "Sky sampling").
  SampledSpectrum eval(const Vec3& dir, const SampledWavelengths& wl) const;
  SampledSpectrum eval_sky(const Vec3& dir, const SampledWavelengths& wl) const;
  LightSample sample(Vec2 u, float u_select, const SampledWavelengths& wl) const;
  // Solid-angle density with which sample() produces `dir`.
  float pdf(const Vec3& dir) const;
  bool empty() const { return p_sun_ == 0 && p_sky_ == 0; }

  const SunDesc& sun() const { return sun_; }
  const SkyDesc& sky() const { return sky_; }
  // Whether `dir` lies in the solar disc: |dir − axis|² ≤ 2(1 − cos α), precise for tiny α. The
  // 1e-5 relative margin absorbs float rounding of directions sampled at the rim, so every sampled
  // direction is inside (the margin changes the disc's solid angle by 1e-5).
  bool in_sun(const Vec3& dir) const {
    const Vec3 d = dir - sun_frame_.z;
    return glm::dot(d, d) <= 2.0f * sun_one_minus_cos_ * (1.0f + 1e-5f);
  }
  const Vec3& sun_axis() const { return sun_frame_.z; }
  const Frame& sun_frame() const { return sun_frame_; }
  float sun_one_minus_cos() const { return sun_one_minus_cos_; }
  // Probability that sample() draws from the sun (else the sky).
  float sun_selection_probability() const { return p_sun_; }
  // Sky radiance spectrum for relative luminance 1 (models whose colour does not vary).
  const DenseSpectrum& sky_radiance_scale() const { return sky_radiance_; }
  // Whether the sky's spectrum varies with direction (a SpectralSkyModel).
  bool spectral_sky() const { return spectral_sky_; }
  // Spectral irradiance on an upward-facing horizontal plane from the sun and the sky above the
  // horizon, W·m⁻²·nm⁻¹ (docs/radiometry.md): the sun disc gives E_sun · max(0, cos θ_sun) (exact
  // for a uniform disc above the horizon: ∫_disc ω dω = axis · π sin²α), the sky its radiance
  // scale times ∫_{z>0} g(ω) cos θ dω on a 256 × 128 (φ, θ) grid (the horizontal diffuse spectrum
  // itself for normalised models). The ground below the horizon does not reach an upward plane.
  DenseSpectrum horizontal_irradiance() const;
  // Test seam (render/testing/faults.h, the golden suite's power tests): from now on eval_sky
  // returns the sky's radiance × `gain` for directions between the horizon and `elevation_deg`.
  // The sampling density and horizontal_irradiance() are left as they were.
  void inject_horizon_fault(float gain, float elevation_deg);

 private:
  float sky_shape(const Vec3& dir) const;
  DenseSpectrum horizontal_irradiance_of_sky() const;
  Vec3 sky_basis_weights(const Vec3& dir) const;
  float sky_pdf(const Vec3& dir) const;
  // The sky's sampling weights per cell (sky_distribution_), the ground's below the horizon.
  std::vector<float> sky_table(float ground_weight) const;
  // A spectral sky's basis scaled to its stated spectrum, from the basis weights and cos θ dω of the
  // normalisation grid's upper cells (sky_basis_, sky_horizontal_spectrum_).
  void fit_spectral_sky(const SkyDesc& sky, const std::vector<std::pair<Vec3, float>>& basis_cells);

  SunDesc sun_;
  SkyDesc sky_;
  Frame sun_frame_;
  float sun_one_minus_cos_ = 0.0f;
  DenseSpectrum sun_radiance_;
  DenseSpectrum sky_radiance_;
  double sky_horizontal_ = 0;  // ∫_{z>0} g(ω) cos θ dω, sr
  // Spectral models: the normalised basis spectra, and the sky's horizontal irradiance.
  bool spectral_sky_ = false;
  std::array<DenseSpectrum, 3> sky_basis_;
  DenseSpectrum sky_horizontal_spectrum_;
  bool has_ground_ = false;
  DenseSpectrum ground_radiance_;  // uniform radiance below the horizon when has_ground_
  // The sky's sampling table over (φ, z = cos θ): u = φ/2π, v = (1 − z)/(1 − z_min), equal solid
  // angle per cell; z_min is −1 for a sky over the whole sphere (or with a ground), else 0.
  Distribution2D sky_distribution_;
  float sky_z_min_ = -1.0f;
  float p_sun_ = 0, p_sky_ = 0;
  float horizon_gain_ = 1.0f, horizon_z_ = 0.0f;  // inject_horizon_fault
};

}  // namespace sylva

#pragma once
// Atmospheric haze: an optional participating medium filling the space below a height `top`
// ([haze] in scene files, docs/scene_format.md; docs/radiometry.md, "Haze").
//
// Extinction at 550 nm follows a height profile, homogeneous σ₀(z) = σ_550 or exponential
// σ₀(z) = σ_550·exp(−(z − z₀)/H), and varies with wavelength by Ångström's law
// σ_t(z, λ) = σ₀(z)·(λ/550 nm)^−α (Ångström 1929). A fraction ω (single-scattering albedo) of each
// collision scatters with the Henyey–Greenstein phase function of asymmetry g; the rest is absorbed.
//
// Because every wavelength shares the height profile, the optical depth along a ray is closed-form
// (τ₀ for 550 nm, τ(λ) = k(λ)·τ₀ with k = (λ/550)^−α), and so is its inverse. Free flight is
// therefore sampled by inverting τ₀ exactly
// (no majorant and no null collisions are needed) for the path's hero wavelength; the other
// carried wavelengths are weighted by one-sample multiple importance sampling over the carried
// wavelengths' free-flight densities (hero wavelength sampling, Wilkie et al. 2014). Shadow rays
// take the transmittance exp(−k·τ₀) itself: it is the expectation ratio tracking estimates
// (Novák et al. 2014), available here in closed form, exact and without random numbers.

#include "core/math.h"
#include "core/rng.h"
#include "core/spectrum.h"

#include <limits>

namespace sylva {

enum class HazeProfile { Homogeneous, Exponential };

struct HazeDesc {
  bool enabled = false;
  HazeProfile profile = HazeProfile::Homogeneous;
  float extinction_550 = 0.0f;                         // σ_550 at the base height, 1/m
  float angstrom = 1.3f;                               // α: σ ∝ λ^−α (about 1.3 for continental aerosol)
  float albedo = 0.9f;                                 // single-scattering albedo ω, the same at every wavelength
  float g = 0.7f;                                      // Henyey–Greenstein asymmetry, (−1, 1)
  float base_height = 0.0f;                            // z₀, m (exponential profile)
  float scale_height = 1000.0f;                        // H, m (exponential profile)
  float top = std::numeric_limits<float>::infinity();  // no haze above this height, m
};

// Henyey–Greenstein (1941) phase function of cos θ between the travel directions before and after.
float henyey_greenstein(float cos_theta, float g);
// A direction after scattering from travel direction `a`, distributed as henyey_greenstein.
Vec3 sample_henyey_greenstein(const Vec3& a, float g, Vec2 u);

class Haze {
 public:
  Haze() = default;
  explicit Haze(const HazeDesc& desc);

  bool enabled() const { return desc_.enabled; }
  const HazeDesc& desc() const { return desc_; }

  // k(λ) = (λ/550)^−α per carried wavelength.
  SampledSpectrum spectral_factor(const SampledWavelengths& wl) const;
  // σ₀ (550 nm) at height z, 1/m.
  double extinction_550(double z) const;
  // τ₀ along o + s·d (d unit) over s ∈ [s0, s1], closed form; may be +∞ (s1 = ∞ downwards).
  double optical_depth(const Vec3& o, const Vec3& d, double s0, double s1) const;
  // The s ≥ s0 where τ₀ over [s0, s] reaches `tau`; +∞ when the ray leaves the haze first.
  double distance_at_depth(const Vec3& o, const Vec3& d, double s0, double tau) const;
  // exp(−k(λ)·τ₀) over [0, t].
  SampledSpectrum transmittance(const Vec3& o, const Vec3& d, float t, const SampledWavelengths& wl) const;

  // Free flight along o + s·d over [0, t_max): the distance of a scattering collision, or +∞ when
  // the path reaches t_max. The distance is drawn for the first carried wavelength (the hero, whose
  // place among the carried ones is uniformly random; Wilkie et al. 2014) and the outcome weighted
  // for every wavelength by the balance heuristic over the carried wavelengths' densities
  // (one-sample MIS, Veach 1997 §9.2.4): `beta` *= f(λ)/mean_j(r_j p_j), `ratio` (r_j = the path's
  // density for wavelength j over the hero's, kept at mean 1; start it at 1) is updated. Bounded
  // weights (≤ 4ω/r), no null collisions. Averaged over the hero's place, E[beta·1{passage}] =
  // exp(−k τ₀) per wavelength and the collision density is ω k σ₀ exp(−k τ₀).
  // `u` is uniform in [0, 1).
  float sample_scattering(const Vec3& o, const Vec3& d, float t_max, const SampledWavelengths& wl, float u,
                          SampledSpectrum& beta, SampledSpectrum& ratio) const;

 private:
  HazeDesc desc_;
  // The interval of s where o + s·d lies below `top`.
  bool segment(const Vec3& o, const Vec3& d, double& s_in, double& s_out) const;
};

}  // namespace sylva

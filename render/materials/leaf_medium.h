#pragma once
// A turbid medium of leaves (the volumetric Fournier–Grindal crown, docs/fournier_grindal.md):
// infinitesimal bi-Lambertian leaves (reflectance ρ(λ), transmittance τ(λ)) with a spherical
// leaf-angle distribution and leaf area density LAD (m²/m³). Ross's turbid-medium theory:
// extinction σ_t = G·LAD with G = 1/2 for spherical leaves, independent of direction and wavelength;
// a collision scatters with albedo ω = ρ + τ.
//
// The phase function, derived by integrating bi-Lambertian scattering over leaf normals n weighted
// by their projected area |n·a| (a the travel direction before the collision, b after, cos β = a·b):
//   ∫ |n·a||n·b| over (n·a)(n·b) < 0 = (4/3)(sin β − β cos β)          (reflection)
//   ∫ |n·a||n·b| over (n·a)(n·b) > 0 = (4/3)(sin β + (π − β) cos β)    (transmission)
// so ω p(a → b) = 2ω(sin β − β cos β)/(3π²) + 2τ cos β/(3π), which integrates to ω over the sphere.
// Backward (β = π) it is 2ρ/(3π), forward (β = 0) 2τ/(3π).

#include "core/math.h"
#include "core/spectrum.h"

namespace sylva {

inline constexpr float kSphericalG = 0.5f;

struct LeafPhase {
  SampledSpectrum reflect{0.0f};   // ρ per carried wavelength
  SampledSpectrum transmit{0.0f};  // τ
  float p_reflect = 0.5f;          // probability of sampling the reflection lobe
};
LeafPhase make_leaf_phase(const SampledSpectrum& reflect, const SampledSpectrum& transmit);

// ω p(a → b) per wavelength (per steradian); `a` is the travel direction before, `b` after.
SampledSpectrum eval_leaf_phase(const LeafPhase& phase, const Vec3& a, const Vec3& b);
// The density of sample_leaf_phase's directions.
float leaf_phase_pdf(const LeafPhase& phase, const Vec3& a, const Vec3& b);

// Samples the physical process: a leaf normal with density ∝ |n·a|, then a cosine-distributed
// direction on the reflected (against a) or transmitted side. `weight` = ω p / pdf.
struct LeafPhaseSample {
  Vec3 direction{0.0f};
  SampledSpectrum weight{0.0f};
  float pdf = 0.0f;
};
bool sample_leaf_phase(const LeafPhase& phase, const Vec3& a, Vec2 u_normal, Vec2 u_direction, float u_lobe,
                       LeafPhaseSample* out);

}  // namespace sylva

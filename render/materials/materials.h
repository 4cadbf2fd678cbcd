#pragma once
// Materials (a closed set: std::variant, so a missing case is a compile error).
//  - Diffuse: Lambertian reflectance ρ(λ).
//  - Leaf: bi-Lambertian — reflects ρ(λ) and transmits τ(λ) diffusely, optionally with different
//    spectra on the back (abaxial) face; ρ + τ ≤ 1 is checked when the material is made.
// Directions are in the local shading frame: z = shading normal on the side the light arrives from
// or leaves to; `wo` points away from the surface towards the previous vertex.

#include "core/math.h"
#include "core/spectrum.h"

#include <string>
#include <variant>

namespace sylva {

struct DiffuseMaterial {
  DenseSpectrum reflectance;
};

struct LeafMaterial {
  DenseSpectrum reflectance_front, transmittance_front;
  DenseSpectrum reflectance_back, transmittance_back;
};

using Material = std::variant<DiffuseMaterial, LeafMaterial>;

// Throws sylva::Error (naming `name`) if any value is outside [0,1] or ρ + τ > 1 anywhere.
Material make_diffuse(const std::string& name, const DenseSpectrum& reflectance);
Material make_leaf(const std::string& name, const DenseSpectrum& reflectance, const DenseSpectrum& transmittance);
Material make_leaf(const std::string& name, const DenseSpectrum& reflectance_front,
                   const DenseSpectrum& transmittance_front, const DenseSpectrum& reflectance_back,
                   const DenseSpectrum& transmittance_back);

// BSDF at a hit, evaluated for the carried wavelengths. `front` is whether `wo` is on the side of
// the geometric normal (the leaf's upper face).
struct BsdfSample {
  Vec3 wi;                // local frame
  SampledSpectrum value;  // f · |cos θi| / pdf
  float pdf = 0;
  bool transmitted = false;
};

class Bsdf {
 public:
  Bsdf(const Material& material, const SampledWavelengths& wl, bool front);

  // f(wo, wi) (no cosine); local frame, z = normal on the wo side.
  SampledSpectrum eval(const Vec3& wo, const Vec3& wi) const;
  float pdf(const Vec3& wo, const Vec3& wi) const;
  // Returns false when no direction could be sampled.
  bool sample(const Vec3& wo, Vec2 u, float u_lobe, BsdfSample* out) const;
  // Hemispherical reflectance + transmittance (for the albedo AOV).
  SampledSpectrum albedo() const { return reflect_ + transmit_; }
  SampledSpectrum reflectance() const { return reflect_; }

 private:
  SampledSpectrum reflect_{0.0f};
  SampledSpectrum transmit_{0.0f};
  float p_reflect_ = 1.0f;  // lobe selection probability
};

}  // namespace sylva

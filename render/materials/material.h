#pragma once
// Materials: a closed set (std::variant, so a missing case is a compile error) that is open to
// extension. Each material type lives in its own file pair and provides
//   static constexpr std::string_view kType;                 // the scene file's `type = "..."`
//   static T create(const std::string& name, const Params&); // reads its own parameters
//   void lobes(wl, front, reflect, transmit) const;           // its diffuse lobes at a hit
// Adding a material = its files + one entry in the `Material` variant below.
//
// Directions are in the local shading frame: z = shading normal on the side the light arrives from
// or leaves to; `wo` points away from the surface towards the previous vertex.

#include "core/math.h"
#include "core/params.h"
#include "core/spectrum.h"
#include "render/materials/diffuse.h"
#include "render/materials/leaf.h"

#include <string>
#include <variant>
#include <vector>

namespace sylva {

// The registered materials.
using Material = std::variant<DiffuseMaterial, LeafMaterial>;

// The material whose kType is `params`' "type" (default "diffuse"), created from `params`.
// Throws ParseError for an unknown type or a bad parameter.
Material create_material(const std::string& name, const Params& params);

// Every material's lobes on the dense 1 nm grid, per face, ρ and τ interleaved per grid point: a
// BSDF at four wavelengths reads four 16-byte pieces, not a line per spectrum and wavelength
// (bench/README.md, "The sky's table and spectral tables"). Built per render from the scene's materials as they are
// then; its values are the materials' own (a lerp of the same grid values, the same bits).
class MaterialLobes {
 public:
  MaterialLobes() = default;
  explicit MaterialLobes(const std::vector<Material>& materials);
  void lobes(uint32_t material, const SampledWavelengths& wl, bool front, SampledSpectrum& reflect,
             SampledSpectrum& transmit) const;

 private:
  struct GridLobes {
    float reflect, transmit;
  };
  std::vector<GridLobes> table_;  // [(2 · material + back) · kLambdaSamples + grid index]
};

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
  // The same from the render's interleaved table (identical values).
  Bsdf(const MaterialLobes& table, uint32_t material, const SampledWavelengths& wl, bool front);

  // f(wo, wi) (no cosine); local frame, z = normal on the wo side.
  SampledSpectrum eval(const Vec3& wo, const Vec3& wi) const;
  float pdf(const Vec3& wo, const Vec3& wi) const;
  // Returns false when no direction could be sampled.
  bool sample(const Vec3& wo, Vec2 u, float u_lobe, BsdfSample* out) const;
  // Hemispherical reflectance + transmittance (for the albedo AOV).
  SampledSpectrum albedo() const { return reflect_ + transmit_; }
  SampledSpectrum reflectance() const { return reflect_; }

 private:
  void select_lobes();  // p_reflect_ from the lobes' albedos

  SampledSpectrum reflect_{0.0f};
  SampledSpectrum transmit_{0.0f};
  float p_reflect_ = 1.0f;  // lobe selection probability
};

}  // namespace sylva

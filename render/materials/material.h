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
#include "core/sampling.h"
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

// Material operations for code outside render/materials/ (none of it switches on material types):
// the spectrum a viewer sees as the material's colour (its front reflectance; the OBJ exporter's
// Kd), and whether the plot sensor's flux budget counts its absorption as the leaves' (fAPAR).
// Each type provides display_reflectance() and kFoliage.
inline const DenseSpectrum& display_reflectance(const Material& material) {
  return std::visit([](const auto& m) -> const DenseSpectrum& { return m.display_reflectance(); }, material);
}
inline bool is_foliage(const Material& material) {
  return std::visit([](const auto& m) { return std::decay_t<decltype(m)>::kFoliage; }, material);
}

// Every material's lobes on the dense 1 nm grid, per face, ρ and τ interleaved per grid point: a
// BSDF at four wavelengths reads four 16-byte pieces, not a line per spectrum and wavelength
// (bench/README.md, "The sky's table and spectral tables"). Built per render from the scene's materials as they are
// then; its values are the materials' own (a lerp of the same grid values, the same bits).
class MaterialLobes {
 public:
  MaterialLobes() = default;
  explicit MaterialLobes(const std::vector<Material>& materials);
  void lobes(uint32_t material, const SampledWavelengths& wl, bool front, SampledSpectrum& reflect,
             SampledSpectrum& transmit) const {
    const GridLobes* grid = &table_[(2 * static_cast<size_t>(material) + (front ? 0 : 1)) * kLambdaSamples];
    const GridPositions g = grid_positions(wl);
    const GridLobes* a[kLambdaCount];
    for (int k = 0; k < kLambdaCount; ++k) a[k] = grid + g.index[k];
    // DenseSpectrum::eval's lerp, four wavelengths at a time.
    const SampledSpectrum r0(a[0][0].reflect, a[1][0].reflect, a[2][0].reflect, a[3][0].reflect);
    const SampledSpectrum r1(a[0][1].reflect, a[1][1].reflect, a[2][1].reflect, a[3][1].reflect);
    const SampledSpectrum t0(a[0][0].transmit, a[1][0].transmit, a[2][0].transmit, a[3][0].transmit);
    const SampledSpectrum t1(a[0][1].transmit, a[1][1].transmit, a[2][1].transmit, a[3][1].transmit);
    reflect = r0 + g.fraction * (r1 - r0);
    transmit = t0 + g.fraction * (t1 - t0);
  }

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
  // Inline, with eval, pdf and sample: they run at every path vertex (bench/README.md).
  Bsdf(const MaterialLobes& table, uint32_t material, const SampledWavelengths& wl, bool front) {
    table.lobes(material, wl, front, reflect_, transmit_);
    select_lobes();
  }

  // f(wo, wi) (no cosine); local frame, z = normal on the wo side.
  SampledSpectrum eval(const Vec3& wo, const Vec3& wi) const {
    const bool same_side = (wo.z > 0) == (wi.z > 0);
    return (same_side ? reflect_ : transmit_) * kInvPi;
  }
  float pdf(const Vec3& wo, const Vec3& wi) const {
    const bool same_side = (wo.z > 0) == (wi.z > 0);
    return select(same_side, p_reflect_, 1.0f - p_reflect_) * cosine_hemisphere_pdf(std::abs(wi.z));
  }
  // Returns false when no direction could be sampled. The lobe is a random choice: selected, not
  // branched on.
  bool sample(const Vec3& wo, Vec2 u, float u_lobe, BsdfSample* out) const {
    Vec3 wi = sample_cosine_hemisphere(u);
    if (wi.z <= 0) return false;
    const bool transmit = u_lobe >= p_reflect_;
    const float side = select(wo.z >= 0, 1.0f, -1.0f);
    wi.z *= select(transmit, -side, side);
    const float lobe_p = select(transmit, 1.0f - p_reflect_, p_reflect_);
    if (lobe_p <= 0) return false;
    out->wi = wi;
    out->pdf = lobe_p * cosine_hemisphere_pdf(std::abs(wi.z));
    out->transmitted = transmit;
    out->value = (transmit ? transmit_ : reflect_) / lobe_p;  // f·cos/pdf = (ρ/π)·cos / (p·cos/π)
    return out->pdf > 0;
  }
  // Hemispherical reflectance + transmittance (for the albedo AOV).
  SampledSpectrum albedo() const { return reflect_ + transmit_; }
  SampledSpectrum reflectance() const { return reflect_; }

 private:
  void select_lobes() {  // p_reflect_ from the lobes' albedos
    const float r = average(reflect_), t = average(transmit_);
    p_reflect_ = (r + t) > 0 ? r / (r + t) : 1.0f;
  }

  SampledSpectrum reflect_{0.0f};
  SampledSpectrum transmit_{0.0f};
  float p_reflect_ = 1.0f;  // lobe selection probability
};

// A copy of `m` with every reflectance (not transmittance) scaled by `factor`: the one
// material-neutral edit scene assembly makes (a dead branch's darker bark).
Material scaled_reflectance(const Material& m, float factor);

}  // namespace sylva

#pragma once
// Bi-Lambertian leaf: reflects ρ(λ) and transmits τ(λ) diffusely, optionally with different spectra
// on the back (abaxial) face; ρ + τ ≤ 1 is checked when the material is made.
//
// Scene file: [materials.NAME] type = "leaf", then either prospect = { N, Cab, Car, Ant, Cbrown, Cw,
// Cm } (PROSPECT-D, core/prospect.h) or reflectance = SPECTRUM, transmittance = SPECTRUM and
// optionally back_reflectance, back_transmittance.

#include "core/params.h"
#include "core/spectrum.h"
#include "render/materials/bsdf.h"
#include "render/materials/hit_context.h"
#include "render/materials/texture.h"

#include <string>
#include <string_view>

namespace sylva {

struct LeafMaterial {
  static constexpr std::string_view kType = "leaf";
  static constexpr bool kFoliage = true;  // the flux budget counts its absorption as the leaves'

  SpectrumTexture reflectance_front, transmittance_front;
  SpectrumTexture reflectance_back, transmittance_back;

  static LeafMaterial create(const std::string& name, const Params& params);
  // A Lambertian reflection and a Lambertian transmission lobe; light arriving at the back face
  // (ctx.front false) sees the back spectra; transmission is reciprocal.
  void add_lobes(const HitContext& ctx, Bsdf& bsdf) const {
    bsdf.add(LambertLobe{(ctx.front ? reflectance_front : reflectance_back).eval(ctx), false});
    bsdf.add(LambertLobe{(ctx.front ? transmittance_front : transmittance_back).eval(ctx), true});
  }
  bool varies() const {
    return reflectance_front.varies() || transmittance_front.varies() || reflectance_back.varies() ||
           transmittance_back.varies();
  }
  const DenseSpectrum& display_reflectance() const { return reflectance_front.spectrum; }
  void scale_reflectance(float factor) {
    reflectance_front *= factor;
    reflectance_back *= factor;
  }
};

// Throw sylva::Error (naming `name`) if any value is outside [0,1] or ρ + τ > 1 anywhere.
LeafMaterial make_leaf(const std::string& name, const DenseSpectrum& reflectance, const DenseSpectrum& transmittance);
LeafMaterial make_leaf(const std::string& name, const DenseSpectrum& reflectance_front,
                       const DenseSpectrum& transmittance_front, const DenseSpectrum& reflectance_back,
                       const DenseSpectrum& transmittance_back);

}  // namespace sylva

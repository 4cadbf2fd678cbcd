#pragma once
// Lambertian material: diffuse reflectance ρ(λ), no transmission.
//
// Scene file: [materials.NAME] type = "diffuse", reflectance = SPECTRUM.

#include "core/params.h"
#include "core/spectrum.h"
#include "render/materials/bsdf.h"
#include "render/materials/hit_context.h"
#include "render/materials/texture.h"

#include <string>
#include <string_view>

namespace sylva {

struct DiffuseMaterial {
  static constexpr std::string_view kType = "diffuse";
  static constexpr bool kFoliage = false;  // the flux budget counts it as bark or ground

  SpectrumTexture reflectance;

  // Reads `reflectance`, or `rgb` (linear sRGB, Smits up-sampling); throws ParseError for a missing or
  // unphysical spectrum.
  static DiffuseMaterial create(const std::string& name, const Params& params);
  // One Lambertian reflection lobe, the same on both faces.
  void add_lobes(const HitContext& ctx, Bsdf& bsdf) const { bsdf.add(LambertLobe{reflectance.eval(ctx), false}); }
  bool varies() const { return reflectance.varies(); }
  const DenseSpectrum& display_reflectance() const { return reflectance.spectrum; }
  void scale_reflectance(float factor) { reflectance *= factor; }
};

// Throws sylva::Error (naming `name`) if the reflectance leaves [0, 1].
DiffuseMaterial make_diffuse(const std::string& name, const DenseSpectrum& reflectance);

}  // namespace sylva

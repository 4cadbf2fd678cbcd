#pragma once
// A material's spectral parameter (a reflectance, a transmittance, an emitted radiance): what a
// material evaluates at a hit context. Today a constant spectrum on the 1 nm grid; a texture
// lookup (OpenImageIO's TextureSystem at ctx.uv) will be a second alternative behind the same
// eval(), and materials that hold one report varies() so the render's table skips them
// (MaterialLobes, render/materials/material.h).

#include "core/spectrum.h"
#include "render/materials/hit_context.h"

namespace sylva {

struct SpectrumTexture {
  DenseSpectrum spectrum;  // the constant value

  // The parameter at the hit, per carried wavelength (ctx.wl must be set).
  SampledSpectrum eval(const HitContext& ctx) const { return spectrum.eval(*ctx.wl); }
  // Whether the value depends on more of the context than the wavelengths (never, today).
  static constexpr bool varies() { return false; }
  // Scales the parameter (a dead branch's darker bark; tests' perturbations).
  SpectrumTexture& operator*=(float factor) {
    spectrum *= factor;
    return *this;
  }
};

}  // namespace sylva

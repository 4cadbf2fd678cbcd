#pragma once
// An emitting surface: a Lambertian emitter of spectral radiance L_e(λ) (the same in every
// direction) on its front face (the side of the geometric normal) or on both, that also reflects
// diffusely with reflectance ρ(λ). The path tracer adds L_e where a camera or BSDF-sampled ray
// meets it and, on triangle meshes, samples it as a light (render/lights/emitters.h), the two
// weighted by MIS (render/integrator.h, "Emission").
//
// Scene file: [materials.NAME] type = "emissive", radiance = SPECTRUM (W·m⁻²·sr⁻¹·nm⁻¹), optionally
// reflectance = SPECTRUM (default 0) and two_sided = BOOL (default false).

#include "core/params.h"
#include "core/spectrum.h"
#include "render/materials/bsdf.h"
#include "render/materials/hit_context.h"
#include "render/materials/texture.h"

#include <string>
#include <string_view>

namespace sylva {

struct EmissiveMaterial {
  static constexpr std::string_view kType = "emissive";
  static constexpr bool kFoliage = false;

  SpectrumTexture radiance;     // L_e, W·m⁻²·sr⁻¹·nm⁻¹
  SpectrumTexture reflectance;  // ρ of its Lambertian reflection
  bool two_sided = false;

  // Throws ParseError for a missing or negative radiance or an unphysical reflectance.
  static EmissiveMaterial create(const std::string& name, const Params& params);
  void add_lobes(const HitContext& ctx, Bsdf& bsdf) const { bsdf.add(LambertLobe{reflectance.eval(ctx), false}); }
  // L_e towards wo: on the front face (ctx.front), or on both faces when two-sided.
  SampledSpectrum emitted(const HitContext& ctx) const {
    return ctx.front || two_sided ? radiance.eval(ctx) : SampledSpectrum(0.0f);
  }
  // Emitted power per unit area over the spectrum, W·m⁻²: π ∫ L_e dλ per emitting face. What the
  // light sampler weighs a surface's share by (render/lights/emitters.h).
  float emitted_power_w_m2() const {
    return static_cast<float>(kPi * radiance.spectrum.integral() * (two_sided ? 2.0 : 1.0));
  }
  bool varies() const { return radiance.varies() || reflectance.varies(); }
  const DenseSpectrum& display_reflectance() const { return reflectance.spectrum; }
  void scale_reflectance(float factor) { reflectance *= factor; }
};

// Throws sylva::Error (naming `name`) for a negative radiance or a reflectance outside [0, 1].
EmissiveMaterial make_emissive(const std::string& name, const DenseSpectrum& radiance, const DenseSpectrum& reflectance,
                               bool two_sided);

}  // namespace sylva

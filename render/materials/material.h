#pragma once
// Materials: a closed set (std::variant, so a missing case is a compile error) that is open to
// extension. Each material type lives in its own file pair and provides
//   static constexpr std::string_view kType;                  // the scene file's `type = "..."`
//   static constexpr bool kFoliage;                           // the flux budget counts it as leaves
//   static T create(const std::string& name, const Params&);  // reads its own parameters
//   void add_lobes(const HitContext&, Bsdf&) const;            // its BSDF's lobes at a hit
//   bool varies() const;                                       // parameters vary over the surface
//   const DenseSpectrum& display_reflectance() const;          // a viewer's colour (OBJ Kd)
//   void scale_reflectance(float factor);                      // every reflectance × factor
// and, if it emits,
//   SampledSpectrum emitted(const HitContext&) const;          // radiance towards wo (ctx.front)
//   float emitted_power_w_m2() const;                          // π ∫ L_e dλ over its faces
// Adding a material = its files + one entry in the `Material` variant below. Nothing outside
// render/materials/ visits material types: it calls the functions below.

#include "core/params.h"
#include "core/spectrum.h"
#include "render/materials/bsdf.h"
#include "render/materials/diffuse.h"
#include "render/materials/emissive.h"
#include "render/materials/hit_context.h"
#include "render/materials/leaf.h"

#include <string>
#include <variant>
#include <vector>

namespace sylva {

// The registered materials.
using Material = std::variant<DiffuseMaterial, LeafMaterial, EmissiveMaterial>;

// The material whose kType is `params`' "type" (default "diffuse"), created from `params`.
// Throws ParseError for an unknown type or a bad parameter.
Material create_material(const std::string& name, const Params& params);

// The BSDF of `material` at `ctx` (ctx.wl and ctx.front set).
Bsdf material_bsdf(const Material& material, const HitContext& ctx);

// Whether `material` emits, and its emitted radiance (W·m⁻²·sr⁻¹·nm⁻¹) towards wo at `ctx`.
bool emits(const Material& material);
SampledSpectrum emitted_radiance(const Material& material, const HitContext& ctx);
// Its emitted power per unit area, W·m⁻² (0 for a material that does not emit): the light
// sampler's weight (render/lights/emitters.h).
float emitted_power_w_m2(const Material& material);

// The spectrum a viewer sees as the material's colour (its front reflectance; the OBJ exporter's
// Kd), and whether the plot sensor's flux budget counts its absorption as the leaves' (fAPAR).
const DenseSpectrum& display_reflectance(const Material& material);
bool is_foliage(const Material& material);

// A copy of `m` with every reflectance (not transmittance) scaled by `factor`: the one
// material-neutral edit scene assembly makes (a dead branch's darker bark).
Material scaled_reflectance(const Material& m, float factor);

// The scene's materials as the render evaluates them at hits. A material whose BSDF depends on the
// wavelengths and the face only (no varying parameter) and is at most kTabulatedLobes Lambertian
// lobes is tabulated: its lobes' albedos on the dense 1 nm grid, per face, interleaved per grid
// point, so a BSDF reads a 16-byte piece per wavelength, not a line per spectrum and
// wavelength (bench/README.md, "The sky's table and spectral tables"). Its values are the
// materials' own (a lerp of the same grid values, the same bits). Other materials are evaluated
// at the hit. Built per render from the scene's materials, which must outlive it.
class MaterialLobes {
 public:
  static constexpr int kTabulatedLobes = 2;

  MaterialLobes() = default;
  explicit MaterialLobes(const std::vector<Material>& materials);

  // The BSDF at `ctx` (ctx.material, ctx.wl and ctx.front set): material_bsdf's, bit for bit.
  Bsdf bsdf(const HitContext& ctx) const {
    const size_t face = 2 * static_cast<size_t>(ctx.material) + (ctx.front ? 0 : 1);
    const Layout& layout = layouts_[face];
    if (!layout.tabulated) return material_bsdf((*materials_)[ctx.material], ctx);
    const GridLobes* grid = &table_[face * kLambdaSamples];
    const GridPositions g = grid_positions(*ctx.wl);
    Bsdf bsdf;
    for (int l = 0; l < layout.count; ++l) {
      // DenseSpectrum::eval's lerp, four wavelengths at a time.
      SampledSpectrum albedo;
      for (int b = 0; b < kLambdaBlocks; ++b) {
        const GridLobes* a[4] = {grid + g.index[4 * b], grid + g.index[4 * b + 1], grid + g.index[4 * b + 2],
                                 grid + g.index[4 * b + 3]};
        const Vec4 v0(a[0][0].albedo[l], a[1][0].albedo[l], a[2][0].albedo[l], a[3][0].albedo[l]);
        const Vec4 v1(a[0][1].albedo[l], a[1][1].albedo[l], a[2][1].albedo[l], a[3][1].albedo[l]);
        albedo.block(b) = v0 + g.fraction.block(b) * (v1 - v0);
      }
      bsdf.add(LambertLobe{albedo, layout.transmission[l]});
    }
    bsdf.finish();
    return bsdf;
  }
  // Whether material `material` emits; its radiance towards wo at `ctx`.
  bool emits(uint32_t material) const { return emits_[material] != 0; }
  SampledSpectrum emitted(const HitContext& ctx) const { return emitted_radiance((*materials_)[ctx.material], ctx); }

 private:
  struct GridLobes {
    float albedo[kTabulatedLobes];
  };
  struct Layout {
    bool tabulated = false;
    int count = 0;
    bool transmission[kTabulatedLobes] = {};
  };
  const std::vector<Material>* materials_ = nullptr;
  std::vector<Layout> layouts_;   // [2 · material + back]
  std::vector<GridLobes> table_;  // [(2 · material + back) · kLambdaSamples + grid index]
  std::vector<uint8_t> emits_;    // [material]
};

}  // namespace sylva

#pragma once
// Emitting surfaces as lights: the scene's emissive triangles (a triangle mesh whose material emits,
// render/materials/emissive.h), every placed copy of them in world space, sampled for next-event
// estimation by emitted power and combined with BSDF sampling by multiple importance sampling
// (Integrator; Veach 1997 §9.2, pbrt-v4's power light sampler and triangle sampling).
//
// Which triangle: with probability ∝ area × the material's emitted power per area (both faces of a
// two-sided emitter); where on it: uniformly. So a point's density per unit world area is
// P(triangle) / area(triangle). Instances are handled by moving each copy's triangles to the world
// (the emitter's size, not the scene's, sets the table's: 64 bytes per emissive triangle and copy).
//
// Not sampled, so their emission counts only where a camera or BSDF-sampled ray meets them (with
// weight 1, unbiased): an emissive material on leaf quads, curves, discs or solids, and every
// emitter of a cyclic plot (a sampled point would have to be the nearest of its periodic copies).
// Deterministic: the table depends on the scene only, in instance then triangle order.

#include "core/math.h"
#include "core/sampling.h"
#include "render/materials/hit_context.h"
#include "render/primitives/ray_hit.h"
#include "render/scene.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace sylva {

// A point on an emitter: its context (p, ng as a hit there decodes it, ns = ng, uv, material and
// ids; the face and wavelengths left to the caller) and its density per m² of world area.
struct EmitterPoint {
  HitContext ctx;
  float pdf_area = 0;
};

class EmitterLights {
 public:
  EmitterLights() = default;
  explicit EmitterLights(const Scene& scene);

  // No emitter to sample: the integrator then draws no random number for one.
  bool empty() const { return triangles_.empty(); }
  size_t size() const { return triangles_.size(); }
  // A triangle by power with u_select, a point uniformly on it with u (pbrt-v4's
  // SampleUniformTriangle, which keeps strata).
  EmitterPoint sample(float u_select, Vec2 u) const;
  // The density per m² with which sample() gives the point `hit` meets: 0 when it is not on one of
  // the sampled emitters (another kind, or a triangle that does not emit).
  float pdf_area(const RayHit& hit) const;

 private:
  struct Triangle {
    Vec3 p0{0.0f}, e1{0.0f}, e2{0.0f};  // world: corner 0 and the edges to corners 1 and 2
    Vec3 ng{0.0f};                      // unit, oriented as a hit's geometric normal
    float area = 0;                     // m²
    uint32_t instance = 0, primitive = 0, material = 0, object_id = 0, prototype = 0;
  };
  std::vector<Triangle> triangles_;
  // Per emissive instance, in instance order: (instance, index of its first triangle above).
  std::vector<std::pair<uint32_t, uint32_t>> first_;
  Distribution1D distribution_;
};

}  // namespace sylva

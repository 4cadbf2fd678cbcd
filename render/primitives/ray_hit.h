#pragma once
// A closest hit as the Embree backend returns it (EmbreeScene::intersect) and the integrator decodes
// it (Integrator::interaction, through the kind's decoder in render/primitives/).

#include "core/math.h"
#include "render/primitives/primitive.h"

#include <cstdint>

namespace sylva {

// `instance` indexes Scene::instances; `primitive` indexes the array of the instance's prototype
// that `kind` names: its triangles (not Embree's quads: render/primitives/triangles.h), leaf quads
// (then Prototype::leaves.stem[primitive], if present, is the tree stem carrying the leaf), solids,
// curves (not a strip's pieces) or discs.
struct RayHit {
  float t = 0;  // along the ray as given (cyclic plots: the unwrapped distance)
  uint32_t instance = 0;
  PrimitiveKind kind = PrimitiveKind::kTriangles;
  uint32_t primitive = 0;
  float u = 0, v = 0;  // a triangle's barycentrics of its 2nd and 3rd corners, a leaf quad's coordinates
  Vec3 normal{0.0f};   // solids: the unit outward normal in object space; curves: the ribbon's
                       // geometric normal in object space (not unit); else unset
};

}  // namespace sylva

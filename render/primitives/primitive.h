#pragma once
// The primitive kinds a prototype holds (render/scene.h: Prototype), one file each under
// render/primitives/ with the kind's validation, object-space bounds, Embree set-up and hit
// decoding: triangles.h (meshes), leaf_quads.h, solids.h (half-space solids), media.h (the turbid
// crowns among them), curves.h and discs.h. This header names the kinds and gathers what every
// stage asks of all of them: validation and bounds. Adding a kind: its file, a row here, a case in
// primitive.cpp, flat_writer.cpp (flatten_prototype), embree_geometry.cpp (attach_prototype),
// EmbreeScene::intersect_cell and Integrator::interaction.

#include "render/scene.h"

#include <cstdint>

namespace sylva {

// Which of a prototype's arrays a hit is on. The order is the order the kinds are attached to a
// prototype's Embree scene (and so their geometry ids' order).
enum class PrimitiveKind : uint8_t { kTriangles, kLeafQuads, kSolids, kCurves, kDiscs };
inline constexpr int kPrimitiveKinds = 5;

// Throws sylva::Error naming the prototype when one of its kinds' arrays disagree in size, index a
// missing vertex or lack a material (each kind's validate_*).
void validate_prototype(const Prototype& p);

// The object-space box of everything `p` draws: the union of its kinds' bounds (each conservative:
// every point of every primitive lies inside). Empty for an empty prototype. What the label sidecar
// reports (scenes/sidecar.cpp), and through each instance's transform the scene's bounds and the
// boxes the instance array and the sweep cull by (EmbreeScene).
Bounds3 prototype_bounds(const Prototype& p);

// The union of `a` and `b`.
inline Bounds3 merged(Bounds3 a, const Bounds3& b) {
  if (!b.empty()) {
    a.extend(b.lo);
    a.extend(b.hi);
  }
  return a;
}

}  // namespace sylva

#pragma once
// Internal to the Embree backend (render/embree_scene.cpp and the kinds' files in
// render/primitives/): what a kind's Embree set-up is given and leaves behind for decoding hits, and
// the buffer helpers they share. Every rtc* call of Sylva is in these files (docs/design.md §6); no
// other header includes Embree's.

#include "geometry/leaf_shape.h"
#include "render/embree_scene.h"
#include "render/primitives/primitive.h"

#include <embree3/rtcore.h>

#include <memory>
#include <vector>

namespace sylva {

// What the leaf filters read (render/primitives/leaf_quads.cpp): the outlines, and the corners and
// stem index Integrator::interaction will read for the closest hit. When every leaf of the geometry
// has one outline (the common case) it is kept here, so a candidate hit costs no load of its own
// leaf's record.
struct LeafFilterData {
  const LeafShape* shapes = nullptr;
  const Vec3* corners = nullptr;
  const int32_t* stems = nullptr;  // null when the leaves carry no stem index
  bool one_shape = false;
  LeafShape shape = LeafShape::Rectangle;
};

// One prototype's Embree scene as its kinds build it (attach_*: each attaches its geometry, counts
// it in `stats` and records what its hits need), then what EmbreeScene reads at every hit.
struct EmbreePrototype {
  // Set up before the kinds attach:
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;      // the prototype's BVH (owned by EmbreeScene)
  bool robust = false;           // robust traversal (large geometry): mesh triangles are not paired
  bool no_shadow_alpha = false;  // TransportFaults::no_shadow_alpha
  EmbreeStats* stats = nullptr;
  // Left by the kinds, read at hits:
  PrimitiveKind kind_of[kPrimitiveKinds] = {};  // by Embree geometry id
  std::vector<uint32_t> mesh_quad_first;        // triangles: MeshQuads::first per Embree quad
  bool curve_strips = false;                    // curves as quad strips (kRibbonSegments per curve)
  std::unique_ptr<LeafFilterData> leaf_filter;  // user data of the leaf geometry (a stable address)

  // Commits `g`, attaches it to `scene` as `kind`'s geometry and releases it.
  void attach(RTCGeometry g, PrimitiveKind kind);
};

// A new index buffer of `g`, a quad geometry, filled with `quads`.
void set_quads(RTCGeometry g, const std::vector<glm::uvec4>& quads);
// A new vertex buffer of `g` filled with `points`.
void set_vertices(RTCGeometry g, const std::vector<Vec3>& points);
// The vertex buffer of `g`: `points` itself, shared with Embree rather than copied, when it has the
// spare element past its end that Embree's 16-byte loads of the last vertex read
// (pad_for_vector_loads: every prototype added by Scene::add_prototype has it); a copy otherwise.
// `points` must outlive the scene and keep its storage (EmbreeScene's contract). Returns the bytes
// shared.
size_t bind_vertices(RTCGeometry g, const std::vector<Vec3>& points);

// Each kind's Embree set-up (in its own file): attaches the prototype's primitives of that kind to
// `e.scene`, if it has any. In PrimitiveKind order, so the geometry ids follow it.
void attach_triangles(EmbreePrototype& e, const Prototype& p);
void attach_leaf_quads(EmbreePrototype& e, const Prototype& p);
void attach_solids(EmbreePrototype& e, const Prototype& p);
void attach_curves(EmbreePrototype& e, const Prototype& p);
void attach_discs(EmbreePrototype& e, const Prototype& p);

// Validates nothing (validate_prototype first): attaches every kind `p` holds, in PrimitiveKind order.
void attach_prototype(EmbreePrototype& e, const Prototype& p);

// Each kind's part of the backend's hit: Embree's primitive id and (u, v) on the kind's geometry
// turned into the RayHit's primitive, (u, v) and normal (geometric normal `ng` as Embree gives it).
// Triangles: the Embree quad's triangle and barycentrics; curves: a strip's piece's curve.
void decode_embree_triangle_hit(const EmbreePrototype& e, unsigned prim, float u, float v, RayHit* hit);
void decode_embree_curve_hit(const EmbreePrototype& e, unsigned prim, const Vec3& ng, RayHit* hit);

}  // namespace sylva

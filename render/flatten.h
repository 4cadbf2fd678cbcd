#pragma once
// A scene flattened into one world-space triangle mesh: what `sylva export` writes as OBJ for
// Embree's pathtracer, and the reference BVH of bench/bench_same_rays.cpp.

#include "geometry/mesh.h"
#include "render/scene.h"

#include <optional>
#include <vector>

namespace sylva {

// Leaf discs become regular polygons of this many sides inscribed in the disc (their area is
// (n/2π)·sin(2π/n) = 95.5 % of the disc's).
inline constexpr int kFlattenedDiscSides = 12;

// What a flattened triangle is made of: a scene material and, for leaf quads, the outline that cuts
// it (an alpha mask over the quad's (u, v), geometry/leaf_shape.h); no outline for everything else.
struct FlatPart {
  uint32_t material = 0;
  std::optional<LeafShape> outline;
  bool operator==(const FlatPart&) const = default;
};

// A scene as one world-space triangle mesh. `mesh.uvs` gives every leaf corner its quad coordinates
// (0,0), (1,0), (1,1), (0,1) and every other vertex (0,0); `part[t]` is triangle t's row of
// `parts`, in the order the parts are first met.
struct FlatScene {
  TriangleMesh mesh;
  std::vector<uint32_t> part;
  std::vector<FlatPart> parts;
};

// Every instance of every prototype in world space, leaf quads split into triangles (0,1,2) and
// (0,2,3), half-space solids polygonised (geometry/solids/solid_mesh.h) in the first material of
// their palette. Normals are transformed by the inverse transpose when the whole scene has them (the
// leaves get their quad's geometric normal). Curves are left out: the grass, because flattened the
// instanced patches would outweigh everything else — the default forest's 10.6 million placed
// blades would be 21 million triangles even as one quad each, about 1.5 GB of OBJ, against 23
// million for its trees (leaf quads split in two) and terrain — and Embree's pathtracer, which the
// OBJ is for, reads no curves; the round curves of distant stems at a level of detail likewise.
FlatScene flatten_scene(const Scene& scene);

}  // namespace sylva

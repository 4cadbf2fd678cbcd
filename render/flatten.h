#pragma once
// A scene flattened into one world-space triangle mesh: what `sylva export` writes as OBJ for
// Embree's pathtracer, and the reference BVH of bench/bench_same_rays.cpp.

#include "geometry/mesh.h"
#include "render/scene.h"

namespace sylva {

// Leaf discs become regular polygons of this many sides inscribed in the disc (their area is
// (n/2π)·sin(2π/n) = 95.5 % of the disc's).
inline constexpr int kFlattenedDiscSides = 12;

// Every instance of every prototype in world space, leaf quads split into triangles (0,1,2) and
// (0,2,3), half-space solids polygonised (geometry/solids/solid_mesh.h). Normals are transformed by
// the inverse transpose when the whole scene has them (the leaves get their quad's geometric
// normal); uvs are dropped. Leaf alpha outlines are lost. Grass curves are left out: flattened, the
// instanced patches would outweigh everything else — the default forest's 10.6 million placed
// blades would be 21 million triangles even as one quad each, about 1.5 GB of OBJ, against 23
// million for its trees (leaf quads split in two) and terrain — and Embree's pathtracer, which the
// OBJ is for, reads no curves.
TriangleMesh flatten_scene(const Scene& scene);

}  // namespace sylva

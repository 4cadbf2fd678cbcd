#pragma once
// Polygonising a half-space solid for other tools (`sylva tree --obj`) and for the triangle-mesh
// comparison bench: the exact faces of an undisplaced polytope, or marching tetrahedra on the
// displaced distance field D (geometry/solids/half_space.h) otherwise.

#include "geometry/mesh.h"
#include "geometry/solids/half_space.h"

namespace sylva {

// The solid's surface, triangles counter-clockwise seen from outside, with normals. For a displaced
// solid, D is sampled on a grid of `cells` cells along the longest side of the solid's bounds
// (cubic cells) and each cell split into six tetrahedra (Kuhn); vertices on shared edges are shared
// and placed by linear interpolation of D. Deterministic.
TriangleMesh solid_surface_mesh(const HalfSpaceSolid& solid, int cells = 96);

}  // namespace sylva

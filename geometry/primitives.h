#pragma once
// Simple shapes for scenes and tests: ground planes, boxes, spheres, cylinders, and a cloud of
// leaf quads (a crown stand-in). All centred on the origin unless stated, Z up, outward normals,
// counter-clockwise triangles seen from outside.

#include "geometry/mesh.h"

#include <cstdint>

namespace sylva {

// A rectangle in the XY plane (normal +Z), size_x × size_y metres, `tiles`×`tiles` quads.
TriangleMesh make_plane(float size_x, float size_y, int tiles = 1);
// An axis-aligned box with its base on z = 0 (a closed surface: 12 triangles, flat normals).
TriangleMesh make_box(const Vec3& size);
// A UV sphere of `rings` latitude bands and 2·rings longitudes, smooth normals.
TriangleMesh make_sphere(float radius, int rings = 24);
// A capped cylinder along +Z from z = 0 to `height`.
TriangleMesh make_cylinder(float radius, float height, int segments = 24);

struct LeafCloudParams {
  Vec3 radii{2.0f, 2.0f, 1.5f};  // ellipsoid semi-axes the leaf centres fill uniformly, m
  int count = 2000;
  float leaf_length_m = 0.12f;
  float leaf_width_m = 0.07f;
  LeafShape shape = LeafShape::Oval;
};
// Leaves with uniformly random centres in the ellipsoid and uniformly random orientations
// (a spherical leaf-angle distribution).
LeafQuads make_leaf_cloud(const LeafCloudParams& params, uint64_t seed);

}  // namespace sylva

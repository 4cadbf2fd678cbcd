#pragma once
// The hit decoding that mesh triangles and leaf quads share, the hits nearly every path meets: a
// kind gives the hit point and normals in object space, and finish_surface_hit moves them to the
// world with GLM's arithmetic in SSE registers (core/simd.h: the same operations in the same order,
// so the same bits).

#include "core/simd.h"
#include "render/materials/hit_context.h"
#include "render/scene.h"
#include "render/sensors/camera.h"

namespace sylva {

// A hit point in object space: the point, the geometric normal (not unit) and, when
// `shading_normals`, an interpolated shading normal (not unit).
struct ObjectSurfaceHit {
  __m128 p, ng, ns;
  bool shading_normals = false;  // ns differs from ng (a mesh with vertex normals)
};

// Sets si.p, si.ng and si.ns from `h` through `inst`'s transform (normals by normal_from_object);
// a degenerate geometric normal becomes −ray.direction, a degenerate shading normal the geometric
// one, and the shading normal is turned to the geometric normal's side.
void finish_surface_hit(const Ray& ray, const Instance& inst, const ObjectSurfaceHit& h, HitContext& si);

}  // namespace sylva

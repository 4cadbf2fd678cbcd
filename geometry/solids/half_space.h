#pragma once
// Convex intersections of half-spaces (Fournier & Grindal §2: "V = ∩ HS_i"), optionally displaced by
// fBm (§2.2 "roughen the hull", §3–4), rendered by direct ray intersection (render/embree_scene.cpp
// wraps intersect_solid as Embree user geometry). Plain data; object space in metres.
//
// A half-space is {x : n·x ≤ h} with n a unit outward normal (the paper writes the same set as
// a x + b y + c z + d ≥ 0 with (a, b, c) = −n, d = h).

#include "core/math.h"
#include "geometry/mesh.h"
#include "geometry/solids/fbm.h"

#include <cstdint>
#include <vector>

namespace sylva {

struct HalfSpace {
  Vec3 normal{0.0f, 0.0f, 1.0f};  // unit, pointing out of the solid
  float offset = 0.0f;            // h: inside iff normal·x ≤ h
};

using ConvexPolytope = std::vector<HalfSpace>;

// max_i (n_i·p − h_i): negative inside, zero on the boundary. Inside, −f is exactly the distance to
// the boundary; outside, f is at most the distance (each term is the distance to one plane, which
// is no more than the distance to the polytope). As a maximum of 1-Lipschitz functions it is
// 1-Lipschitz.
float polytope_distance(const ConvexPolytope& planes, const Vec3& p);

// The ray o + t d clipped against every plane (the exact intersection of §2.2, done per ray rather
// than per pixel register): entry = max over front-facing planes (n·d < 0), exit = min over
// back-facing planes (n·d > 0); a plane parallel to the ray rejects it when o is outside. The
// returned span is [t_entry, t_exit] with the planes that produced them (-1 for ±∞); empty when
// t_entry > t_exit.
struct RaySpan {
  double t_entry = -std::numeric_limits<double>::infinity();
  double t_exit = std::numeric_limits<double>::infinity();
  int entry_plane = -1, exit_plane = -1;
  bool empty() const { return !(t_entry <= t_exit); }
};
RaySpan clip_ray(const ConvexPolytope& planes, const Vec3& o, const Vec3& d);

// The boundary of the polytope as convex polygons (one per non-redundant plane, vertices counter-
// clockwise seen from outside), found by clipping a cube of half-size `extent` by every plane in
// turn. `bounded` is false when a face of the starting cube survives (the planes do not enclose a
// region inside it).
struct PolytopeFaces {
  std::vector<std::vector<Vec3>> polygons;
  std::vector<int> plane;  // the half-space each polygon lies on, -1 for a cube face
  bool bounded = true;
};
PolytopeFaces polytope_faces(const ConvexPolytope& planes, float extent);

// Volume (divergence theorem over the face fans) and a triangulation of the faces.
double polytope_volume(const PolytopeFaces& faces);
TriangleMesh polytope_mesh(const PolytopeFaces& faces);

// The polytope with every plane pushed out by `distance` (the set {f ≤ distance}).
ConvexPolytope grow_polytope(const ConvexPolytope& planes, float distance);

// How a solid's surface picks one entry of its material palette (render/scene.h Prototype::solids).
struct SolidColouring {
  enum class Kind : uint8_t {
    Fbm,    // §4: the fBm texture solid, quantised into palette entries of equal probability
    Cells,  // §5: one uniformly drawn palette entry per cubic cell of `cell_m` (bark "at each point")
  };
  Kind kind = Kind::Fbm;
  FbmParams fbm;
  float cell_m = 0.02f;
  uint64_t seed = 1;
};

// A solid: the polytope's distance displaced by fBm, D(p) = f(p) + A·fbm(p), the solid being D ≤ 0.
// With A = 0 it is the exact polytope. Because |fbm| ≤ 1 the solid lies between the polytope shrunk
// by A and the polytope grown by A, so `bounds` (of the grown polytope) contain it.
struct HalfSpaceSolid {
  ConvexPolytope planes;
  float displacement_m = 0.0f;  // A
  FbmParams displacement;
  SolidColouring colouring;
  uint8_t material_slot = 0;  // 0 = bark (trunk), 1 = foliage (crown)
  // > 0: the solid is a turbid medium of leaves of this leaf area density (m²/m³ of world space),
  // not an opaque surface; its boundary is crossed, not shaded (render/materials/leaf_medium.h).
  float leaf_area_density = 0.0f;
  Bounds3 bounds;          // object-space bounds of every point of the solid
  float lipschitz = 1.0f;  // of D: 1 + A·fbm_lipschitz (solid_lipschitz)
};

// The half-size of the cube polytope_faces starts from for solids: no crown or trunk reaches 1 km
// from its tree's origin.
inline constexpr float kSolidExtentM = 1e3f;

// Fills `bounds` and `lipschitz` from the planes and displacement; throws sylva::Error when the
// planes do not enclose a bounded, non-empty region within `extent_m` of the origin.
void finish_solid(HalfSpaceSolid& solid, float extent_m = kSolidExtentM);

// D(p) and its Lipschitz constant. Proof of the bound: |D(p) − D(q)| ≤ |f(p) − f(q)| +
// A|fbm(p) − fbm(q)| ≤ (1 + A·L_fbm)|p − q| (f is 1-Lipschitz, see polytope_distance; L_fbm is
// fbm_lipschitz, proven in fbm.cpp). So |D(p)|/L never exceeds the distance from p to the surface
// D = 0, and a sphere-tracing step of that length cannot cross it.
float solid_distance(const HalfSpaceSolid& solid, const Vec3& p);
float solid_lipschitz(const HalfSpaceSolid& solid);

// The first crossing of the surface along o + t d with t in (t_min, t_max): exact plane clipping for
// an undisplaced solid (the hit normal is the plane's), sphere tracing otherwise (steps of
// |D|/(L|d|), at least `kMinStep` of the solid's size, then bisection once D changes sign; the
// normal is D's gradient by central differences). Rays starting inside find the way out. `normal`
// is unit and points out of the solid. Deterministic; safe to call from any thread.
struct SolidHit {
  float t = 0.0f;
  Vec3 normal{0.0f};
};
bool intersect_solid(const HalfSpaceSolid& solid, const Vec3& o, const Vec3& d, float t_min, float t_max,
                     SolidHit* hit);

// The palette entry (of `count`) at object-space point p.
uint32_t solid_palette_index(const SolidColouring& colouring, const Vec3& p, uint32_t count);

}  // namespace sylva

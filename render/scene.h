#pragma once
// The renderer's scene: a backend-neutral description of geometry (prototypes and instances),
// materials, the distant light, the camera and an optional haze. Built by scenes/ (assembly) and consumed by the
// Embree backend (render/embree_scene.*) and the integrator. Plain data, index handles.

#include "geometry/grass.h"
#include "geometry/leaf_discs.h"
#include "geometry/mesh.h"
#include "geometry/solids/half_space.h"
#include "render/lights/lights.h"
#include "render/materials/material.h"
#include "render/media/haze.h"
#include "render/sensors/camera.h"

#include <map>
#include <string>
#include <vector>

namespace sylva {

// A unique mesh (one BVH): triangles (bark, ground, targets), leaf quads, solids and/or curves,
// each with a material.
struct Prototype {
  std::string name;
  TriangleMesh triangles;
  uint32_t triangle_material = 0;
  LeafQuads leaves;
  uint32_t leaf_material = 0;
  // Solids intersected exactly (Fournier–Grindal crowns and trunks: Embree user geometry), each
  // with a palette of materials its colouring picks from (solid_palette_index); one palette per
  // solid, never empty.
  std::vector<HalfSpaceSolid> solids;
  std::vector<std::vector<uint32_t>> solid_palettes;
  // Thin two-sided ribbons (grass blades: cubic Bézier ribbons, traced as triangle strips) in
  // `curve_material` (a leaf material: reflectance and transmittance), or round tubes
  // (CurveSet::round: stems drawn as lines at range, geometry/trees/lod.h) in a bark material.
  CurveSet curves;
  uint32_t curve_material = 0;
  // Leaves as exact discs (RAMI abstract canopies, [[leaves]] files), two-sided with this leaf
  // material.
  LeafDiscs discs;
  uint32_t disc_material = 0;
};

// The built-in classes of the class table (Scene::class_names, the `id.class` AOV). Every other
// class (a species, a target label, a [[meshes]] `class`) has an id from its name alone, in
// [kFirstNamedClass, kMaxClassId) — the same in every scene and study (scenes/sections/scene_builder.h,
// class_id_of; docs/scene_format.md "Label AOVs").
inline constexpr uint32_t kClassSky = 0;           // no hit
inline constexpr uint32_t kClassTerrain = 1;       // [terrain]
inline constexpr uint32_t kClassGrass = 2;         // grass patches
inline constexpr uint32_t kClassMesh = 3;          // [[meshes]] without a `label`
inline constexpr uint32_t kFirstNamedClass = 16;   // ids 4..15 are kept for later built-ins
inline constexpr uint32_t kMaxClassId = 1u << 24;  // `id.class` is a float AOV, exact up to 2^24

// The largest object id: ids are written to the float AOV `id.object`, exact up to 2^24.
inline constexpr uint32_t kMaxObjectId = 1u << 24;

// A placed copy of a prototype. `world_from_object` is an affine transform.
struct Instance {
  uint32_t prototype = 0;
  Mat4 world_from_object{1.0f};
  uint32_t object_id = 0;          // label written to the `id.object` AOV (e.g. a class or target id); 0 = none
  uint32_t class_id = kClassMesh;  // key of Scene::class_names, written to `id.class`
  uint32_t variant_id = 0;         // 1 + row of the scene file's variant table (a tree's species + seed); 0 = none
};

// The transform of an instance's normals up to a positive factor (every caller normalises): the
// inverse transpose of the linear part M = [a b c] is [b×c c×a a×b] / det M, here without the
// division, times the sign of det M. Computed per hit rather than stored per instance (36 bytes
// each; millions of instances, bench/README.md).
inline Mat3 normal_from_object(const Instance& inst) {
  const Mat3 m(inst.world_from_object);
  const Mat3 cofactors(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
  return glm::dot(m[0], cofactors[0]) < 0 ? -cofactors : cofactors;
}

// A rectangular plot [lo, hi] in x and y (docs/radiometry.md): what the plot sensor and the flux
// accounting measure. When `cyclic`, the world is periodic: the scene's content is one period and
// repeats with periods hi − lo in x and y, so a ray leaving the plot on one side re-enters it on the
// other (EmbreeScene). Content may reach at most one period beyond the plot.
struct PlotDesc {
  bool defined = false;
  Vec2 lo{0.0f}, hi{0.0f};
  bool cyclic = false;
};

// How placed instances reach the ray tracer (render/embree_scene.h): one Embree instance per copy
// (`native`), one user geometry over all of them (`array`: about a quarter of the memory and a
// fraction of the build time per instance), native instances traced by the sweep instead of
// Embree's instance BVH (`sweep`, at most InstanceBoxes::kMaxCopies: render/instance_sweep.h), or
// `automatic`: the sweep up to kMaxCopies Embree instances, native below kInstanceArrayThreshold,
// the array from there on. The scene file's `[render] instancing`.
enum class InstanceLevel : uint8_t { automatic, native, array, sweep };

// Gives `points` exactly one spare element of capacity past its end, zeroed (any other spare
// capacity is shed). Embree reads each vertex with a 16-byte load, so the last one's load reaches 4
// bytes past the array ("the last buffer element must be readable using 16-byte SSE load
// instructions", rtcSetSharedGeometryBuffer(3)): with that spare element Embree can use the array
// itself as a vertex buffer instead of a copy of it (EmbreeScene). Zeroed so that what the load
// reads is the same on every run.
inline void pad_for_vector_loads(std::vector<Vec3>& points) {
  if (points.empty()) return;
  if (points.capacity() != points.size() + 1) {
    std::vector<Vec3> padded;
    padded.reserve(points.size() + 1);
    padded.assign(points.begin(), points.end());
    points = std::move(padded);
  }
  points.push_back(Vec3(0.0f));  // within the capacity: writes the spare element, no reallocation
  points.pop_back();
}

struct Scene {
  std::vector<Material> materials;
  std::vector<std::string> material_names;
  std::vector<Prototype> prototypes;
  std::vector<Instance> instances;
  SunDesc sun;
  SkyDesc sky;
  CameraDesc camera;
  // The `id.class` table: class id → name (kClassSky ... kClassMesh, then the named classes used).
  std::map<uint32_t, std::string> class_names{
      {kClassSky, "sky"}, {kClassTerrain, "terrain"}, {kClassGrass, "grass"}, {kClassMesh, "mesh"}};
  HazeDesc haze;  // optional atmospheric haze (render/media/haze.h); off by default
  PlotDesc plot;
  InstanceLevel instance_level = InstanceLevel::automatic;

  uint32_t add_material(std::string name, Material material) {
    material_names.push_back(std::move(name));
    materials.push_back(std::move(material));
    return static_cast<uint32_t>(materials.size() - 1);
  }
  // Adds `p`, its vertex arrays padded for Embree to share them (pad_for_vector_loads).
  uint32_t add_prototype(Prototype p) {
    pad_for_vector_loads(p.triangles.positions);
    pad_for_vector_loads(p.leaves.corners);
    prototypes.push_back(std::move(p));
    return static_cast<uint32_t>(prototypes.size() - 1);
  }
};

}  // namespace sylva

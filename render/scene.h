#pragma once
// The renderer's scene: a backend-neutral description of geometry (prototypes and instances),
// materials, the distant light, the camera and an optional haze. Built by scenes/ (assembly) and consumed by the
// Embree backend (render/embree_scene.*) and the integrator. Plain data, index handles.

#include "geometry/mesh.h"
#include "geometry/solids/half_space.h"
#include "render/lights/lights.h"
#include "render/materials/material.h"
#include "render/media/haze.h"
#include "render/sensors/camera.h"

#include <string>
#include <vector>

namespace sylva {

// A unique mesh (one BVH): triangles (bark, ground, targets) and/or leaf quads, each with a material.
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
};

// A placed copy of a prototype. `world_from_object` is an affine transform.
struct Instance {
  uint32_t prototype = 0;
  Mat4 world_from_object{1.0f};
  uint32_t object_id = 0;  // label written to the `id.object` AOV (e.g. a class or target id); 0 = none
};

struct Scene {
  std::vector<Material> materials;
  std::vector<std::string> material_names;
  std::vector<Prototype> prototypes;
  std::vector<Instance> instances;
  SunDesc sun;
  SkyDesc sky;
  CameraDesc camera;
  HazeDesc haze;  // optional atmospheric haze (render/media/haze.h); off by default

  uint32_t add_material(std::string name, Material material) {
    material_names.push_back(std::move(name));
    materials.push_back(std::move(material));
    return static_cast<uint32_t>(materials.size() - 1);
  }
  uint32_t add_prototype(Prototype p) {
    prototypes.push_back(std::move(p));
    return static_cast<uint32_t>(prototypes.size() - 1);
  }
};

}  // namespace sylva

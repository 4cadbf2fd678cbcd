#include "scenes/sections/terrain_grass.h"

#include "core/error.h"
#include "geometry/grass.h"
#include "geometry/placement.h"
#include "scenes/forest_rasters.h"

#include <fmt/core.h>

namespace sylva {

namespace {

// A terrain from an elevation raster (any one-channel image OpenImageIO reads, 16-bit integer or
// float); sets the builder's extent.
HeightField read_raster_terrain(const Params& t, int step, SceneBuilder& b) {
  for (const char* key : {"size", "centre", "resolution", "relief", "feature_size", "octaves", "gain", "noise", "seed"})
    if (t.has(key)) t.fail(key, fmt::format("'{}' is for a procedural terrain (one without 'file')", key));
  ElevationRaster er;
  er.metres_per_pixel = t.real("metres_per_pixel", 1.0, 1e-3, 1e5);
  er.vertical_scale = t.real("vertical_scale", 1.0, 0.0, 1e5);
  er.height_offset_m = t.real("height_offset", 0.0, -1e5, 1e5);
  if (t.has("origin")) er.origin_m = t.vec2("origin", Vec2(0.0f));
  er.step = step;
  try {
    return read_elevation_raster(t.file_path("file"), er, &b.extent_min, &b.extent_max);
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    t.fail("file", e.what());
  }
}

// A procedural fBm or ridged terrain; sets the builder's extent.
HeightField make_noise_terrain(const Params& t, int step, SceneBuilder& b) {
  for (const char* key : {"metres_per_pixel", "vertical_scale", "height_offset", "origin"})
    if (t.has(key)) t.fail(key, fmt::format("'{}' is for a terrain from a raster ('file')", key));
  ProceduralTerrainParams pt;
  pt.size_m = t.vec2("size", pt.size_m);
  if (!(pt.size_m.x > 0 && pt.size_m.y > 0 && pt.size_m.x <= 1e6f && pt.size_m.y <= 1e6f))
    t.fail("size", "size = [x, y] must be positive metres, at most 1e6");
  pt.centre_m = t.vec2("centre", pt.centre_m);
  pt.resolution_m = t.real("resolution", pt.resolution_m, 1e-3, 1e5) * static_cast<float>(step);
  pt.relief_m = t.real("relief", pt.relief_m, 0.0, 1e5);
  pt.feature_size_m = t.real("feature_size", pt.feature_size_m, 1e-2, 1e7);
  pt.octaves = static_cast<int>(t.integer("octaves", pt.octaves, 1, 16));
  pt.gain = t.real("gain", pt.gain, 0.0, 1.0);
  const std::string noise = t.string("noise", "fbm");
  if (noise != "fbm" && noise != "ridged") t.fail("noise", "noise must be \"fbm\" or \"ridged\"");
  pt.ridged = noise == "ridged";
  pt.seed = static_cast<uint64_t>(t.integer("seed", 1, 0, INT64_MAX));
  if (static_cast<double>(pt.size_m.x / pt.resolution_m) * static_cast<double>(pt.size_m.y / pt.resolution_m) >
      kMaxTerrainNodes)
    t.fail("resolution",
           fmt::format("the terrain would have more than {:g} nodes: raise resolution or step", kMaxTerrainNodes));
  HeightField terrain = make_procedural_terrain(pt);
  b.extent_min = pt.centre_m - 0.5f * pt.size_m;
  b.extent_max = pt.centre_m + 0.5f * pt.size_m;
  return terrain;
}

}  // namespace

void parse_terrain(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("terrain");
  t->check_keys({"file", "metres_per_pixel", "vertical_scale", "height_offset", "origin", "step", "material",
                 "object_id", "size", "centre", "resolution", "relief", "feature_size", "octaves", "gain", "noise",
                 "seed"});
  const uint32_t material = b.material_ref(*t, "material");
  const int step = static_cast<int>(t->integer("step", 1, 1, 4096));
  b.terrain = t->has("file") ? read_raster_terrain(*t, step, b) : make_noise_terrain(*t, step, b);
  const HeightField& terrain = *b.terrain;
  if (static_cast<double>(terrain.width) * terrain.height > kMaxTerrainNodes)
    t->fail("step", fmt::format("the terrain has {} x {} nodes, more than {:g}: raise step", terrain.width,
                                terrain.height, kMaxTerrainNodes));
  if (b.camera_above_terrain) {
    CameraDesc& c = b.scene().camera;
    c.position.z += terrain_height(terrain, Vec2(c.position));
    c.target.z += terrain_height(terrain, Vec2(c.target));
  }
  Prototype p;
  p.name = "terrain";
  p.triangles = make_terrain_mesh(terrain);
  p.triangle_material = material;
  const uint32_t proto = b.scene().add_prototype(std::move(p));
  b.scene().instances.push_back(
      Instance{proto, Mat4(1.0f), static_cast<uint32_t>(t->integer("object_id", 0, 0, 1 << 24)), kClassTerrain, 0});
}

void parse_grass(const Params& root, SceneBuilder& b) {
  for (const Params* t : root.tables("grass")) {
    if (b.grass.size() == kFeatureGrassTypes)
      t->fail("at most 3 [[grass]] types (a feature map's 2 grass bits choose one of 3)");
    t->check_keys({"name", "material", "density", "length", "width", "bend", "patch_size", "seed", "trace"});
    GrassParams g;
    g.density_per_m2 = t->real("density", g.density_per_m2, 0.0, 1e5);
    g.length_m = read_range(*t, "length", g.length_m, 1e-3, 10.0);
    g.width_m = t->real("width", g.width_m, 1e-5, 1.0);
    g.bend = t->real("bend", g.bend, 0.0, 1.0);
    g.patch_size_m = t->real("patch_size", g.patch_size_m, 0.1, 100.0);
    Prototype p;
    p.name = t->string("name", fmt::format("grass {}", b.grass.size() + 1));
    p.curve_material = b.material_ref(*t, "material");
    try {
      p.curves = make_grass_patch(g, static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX)));
    } catch (const Error& e) {
      t->fail("density", e.what());
    }
    const std::string trace = t->string("trace", "strips");
    if (trace != "strips" && trace != "curves") t->fail("trace", "trace must be \"strips\" or \"curves\"");
    p.curves.exact = trace == "curves";
    b.grass.push_back({b.scene().add_prototype(std::move(p)), g.patch_size_m});
  }
}

}  // namespace sylva

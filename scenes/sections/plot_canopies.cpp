#include "scenes/sections/plot_canopies.h"

#include "core/error.h"
#include "geometry/leaf_discs.h"

#include <fmt/core.h>

#include <cmath>

namespace sylva {

namespace {

// views = [[zenith, azimuth], ...] and principal_plane = [from, to, step], in degrees.
void read_plot_views(const Params& t, float sun_azimuth_deg, PlotSettings& ps) {
  if (const ParamValue* views = t.get("views")) {
    if (views->kind != ParamValue::Kind::Array) t.fail("views", "views = [[zenith, azimuth], ...] in degrees");
    for (const ParamValue& v : views->array) {
      if (v.kind != ParamValue::Kind::Array || v.array.size() != 2 || !v.array[0].is_number() ||
          !v.array[1].is_number())
        t.fail("views", "each view is [zenith, azimuth] in degrees");
      const double zenith = v.array[0].number(), azimuth = v.array[1].number();
      if (!(zenith >= 0 && zenith <= 89.9) || !(azimuth >= -360 && azimuth <= 360))
        t.fail("views", "view zenith must be in [0, 89.9] and azimuth in [-360, 360] degrees");
      ps.views.push_back(PlotView{static_cast<float>(zenith), static_cast<float>(azimuth), static_cast<float>(zenith)});
    }
  }
  if (t.has("principal_plane")) {
    const std::vector<double> pp = t.numbers("principal_plane");
    if (pp.size() != 3) t.fail("principal_plane", "principal_plane = [from, to, step] in degrees");
    try {
      const std::vector<PlotView> v = principal_plane_views(static_cast<float>(pp[0]), static_cast<float>(pp[1]),
                                                            static_cast<float>(pp[2]), sun_azimuth_deg);
      ps.views.insert(ps.views.end(), v.begin(), v.end());
    } catch (const Error& e) {
      t.fail("principal_plane", e.what());
    }
  }
  if (ps.views.size() > 100000) t.fail("views", "at most 100000 view directions");
}

// A homogeneous canopy: a layer of discs over `size` at `centre` (the [plot]'s by default).
LeafDiscs make_homogeneous_canopy(const Params& t, const PlotDesc& plot, float radius, LeafAngles angles,
                                  uint64_t seed) {
  for (const char* key : {"sphere_radius", "centres", "centres_file"})
    if (t.has(key)) t.fail(key, fmt::format("'{}' is for type = \"spheres\"", key));
  const Vec2 size = t.vec2("size", plot.defined ? plot.hi - plot.lo : Vec2(0.0f));
  if (!(size.x > 0 && size.y > 0)) t.fail("size", "a homogeneous canopy needs size = [x, y] (or a [plot] to cover)");
  const Vec2 centre = t.vec2("centre", plot.defined ? 0.5f * (plot.lo + plot.hi) : Vec2(0.0f));
  return make_homogeneous_layer(centre - 0.5f * size, centre + 0.5f * size,
                                static_cast<float>(t.real("height", 1.0, 1e-3, 1e4)),
                                static_cast<float>(t.real("lai", 1.0, 1e-3, 100.0)), radius, angles, seed);
}

// The centres of a spheres canopy: centres = [[x, y, z], ...] or centres_file.
std::vector<Vec3> read_sphere_centres(const Params& t) {
  for (const char* key : {"height", "size", "centre"})
    if (t.has(key)) t.fail(key, fmt::format("'{}' is for type = \"homogeneous\"", key));
  if (t.has("centres") == t.has("centres_file"))
    t.fail("spheres need either centres = [[x, y, z], ...] or centres_file, not both");
  if (t.has("centres_file")) return read_points(t.file_path("centres_file"));
  const ParamValue* c = t.get("centres");
  std::vector<Vec3> at;
  if (c->kind == ParamValue::Kind::Array)
    for (const ParamValue& v : c->array) {
      if (v.kind != ParamValue::Kind::Array || v.array.size() != 3) break;
      Vec3 q;
      for (int k = 0; k < 3; ++k) q[k] = static_cast<float>(v.array[k].is_number() ? v.array[k].number() : NAN);
      if (!std::isfinite(q.x + q.y + q.z)) break;
      at.push_back(q);
    }
  if (at.empty() || (c->kind == ParamValue::Kind::Array && at.size() != c->array.size()))
    t.fail("centres", "centres = [[x, y, z], ...] in metres");
  return at;
}

}  // namespace

// The rectangle the plot sensor measures (size, centre), whether the world repeats it (cyclic),
// the view directions, sample counts and the materials counted as ground.
void parse_plot(const Params& root, SceneBuilder& b) {
  const Params* t = root.table("plot");
  t->check_keys({"size", "centre", "cyclic", "views", "principal_plane", "samples", "flux_samples", "ground"});
  PlotDesc& plot = b.scene().plot;
  const Vec2 size = t->vec2("size", Vec2(0.0f));
  if (!(size.x > 0 && size.y > 0 && size.x <= 1e6f && size.y <= 1e6f))
    t->fail("size", "[plot] needs size = [x, y], positive metres (at most 1e6)");
  const Vec2 centre = t->vec2("centre", Vec2(0.0f));
  if (!(std::abs(centre.x) <= kMaxSceneCoordinate_m && std::abs(centre.y) <= kMaxSceneCoordinate_m))
    t->fail("centre", fmt::format("the plot centre must lie within {:g} m of the origin", kMaxSceneCoordinate_m));
  plot.defined = true;
  plot.lo = centre - 0.5f * size;
  plot.hi = centre + 0.5f * size;
  plot.cyclic = t->boolean("cyclic", false);
  PlotSettings& ps = b.file().plot;
  ps.samples = static_cast<int>(t->integer("samples", ps.samples, 1, 1 << 30));
  ps.flux_samples = static_cast<int>(t->integer("flux_samples", ps.flux_samples, 1, 1 << 30));
  read_plot_views(*t, b.scene().sun.azimuth_deg, ps);
  if (t->has("ground"))
    for (const std::string& name : t->strings("ground")) {
      const std::optional<uint32_t> id = b.find_material(name);
      if (!id) t->fail("ground", "unknown material '" + name + "'");
      ps.ground_materials.push_back(*id);
    }
}

// Leaf discs read from a RAMI leaf file (radius cx cy cz nx ny nz per row), one prototype
// instanced like a mesh.
void parse_leaves(const Params& root, SceneBuilder& b) {
  for (const Params* t : root.tables("leaves")) {
    t->check_keys({"name", "file", "material", "translate", "rotate", "scale", "object_id", "instances", "tile"});
    Prototype p;
    p.name = t->string("name", fmt::format("leaves{}", b.scene().prototypes.size()));
    p.disc_material = b.material_ref(*t, "material");
    p.discs = read_leaf_discs(t->file_path("file"));
    b.place(*t, b.scene().add_prototype(std::move(p)));
  }
}

// type = "homogeneous" (a layer of discs over a rectangle) or "spheres" (one sphere of discs
// instanced at each centre).
void parse_canopies(const Params& root, SceneBuilder& b) {
  for (const Params* t : root.tables("canopies")) {
    t->check_keys({"name", "type", "material", "lai", "height", "size", "centre", "disc_radius", "leaf_angles", "seed",
                   "sphere_radius", "centres", "centres_file", "translate", "rotate", "scale", "object_id", "instances",
                   "tile"});
    const std::string type = t->string("type");
    Prototype p;
    p.name = t->string("name", fmt::format("canopy{}", b.scene().prototypes.size()));
    p.disc_material = b.material_ref(*t, "material");
    const float radius = static_cast<float>(t->real("disc_radius", 0.1, 1e-4, 100.0));
    const uint64_t seed = static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX));
    LeafAngles angles = LeafAngles::spherical;
    try {
      angles = parse_leaf_angles(t->string("leaf_angles", "uniform"));
    } catch (const Error& e) {
      t->fail("leaf_angles", e.what());
    }
    std::vector<Vec3> at{Vec3(0.0f)};
    try {
      if (type == "homogeneous") {
        p.discs = make_homogeneous_canopy(*t, b.scene().plot, radius, angles, seed);
      } else if (type == "spheres") {
        at = read_sphere_centres(*t);
        p.discs = make_leaf_sphere(static_cast<float>(t->real("sphere_radius", 10.0, 1e-3, 1e4)),
                                   static_cast<float>(t->real("lai", 5.0, 1e-3, 100.0)), radius, angles, seed);
      } else {
        t->fail("type", "canopy type must be \"homogeneous\" or \"spheres\", not \"" + type + "\"");
      }
    } catch (const ParseError&) {
      throw;
    } catch (const Error& e) {
      t->fail(e.what());
    }
    b.place(*t, b.scene().add_prototype(std::move(p)), kClassMesh, 0, at);
  }
}

}  // namespace sylva

#include "scenes/scene_file.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "core/prospect.h"
#include "core/registry.h"
#include "core/rgb_spectrum.h"
#include "geometry/grass.h"
#include "geometry/ground.h"
#include "geometry/leaf_discs.h"
#include "geometry/mesh_io.h"
#include "geometry/placement.h"
#include "geometry/primitives.h"
#include "geometry/terrain.h"
#include "geometry/trees/tree_mesher.h"
#include "scenes/forest_rasters.h"
#include "scenes/placement_list.h"
#include "scenes/species.h"
#include "scenes/toml_reader.h"
#include "scenes/tree_lod.h"
#include "scenes/tree_variants.h"

#include <fmt/core.h>
#include <tbb/parallel_for.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <type_traits>
#include <variant>

namespace sylva {

namespace {

const char* const kDefaultSceneText =
#include "scenes/default_scene.inc"
    ;

uint64_t hash_text(std::string_view text) { return mix64(fnv1a64(text)); }

// Builds a SceneFile from the document's sections. Each section is parsed by its own small function
// (the table in parse()); materials, primitives and sky models are chosen through registries, and
// each type reads its own parameters.
class SceneParser {
 public:
  SceneParser(const Params& root, std::filesystem::path base_dir, const SceneOptions& options)
      : root_(root), base_dir_(std::move(base_dir)), options_(options) {}

  SceneFile parse() {
    using Section = void (SceneParser::*)(const Params&);
    // Sections in the order they are parsed (materials before the meshes and trees that use them).
    static constexpr std::pair<std::string_view, Section> kSections[] = {
        {"render", &SceneParser::parse_render},
        {"bands", &SceneParser::parse_bands},
        {"camera", &SceneParser::parse_camera},
        {"lod", &SceneParser::parse_lod},
        {"sun", &SceneParser::parse_sun},
        {"sky", &SceneParser::parse_sky},
        {"haze", &SceneParser::parse_haze},
        {"materials", &SceneParser::parse_materials},
        {"plot", &SceneParser::parse_plot},
        {"meshes", &SceneParser::parse_meshes},
        {"trees", &SceneParser::parse_trees},
        {"leaves", &SceneParser::parse_leaves},
        {"canopies", &SceneParser::parse_canopies},
        {"terrain", &SceneParser::parse_terrain},
        {"grass", &SceneParser::parse_grass},
        {"vegetation", &SceneParser::parse_vegetation},
        {"placements", &SceneParser::parse_placements},
        {"targets", &SceneParser::parse_targets},
        {"output", &SceneParser::parse_output},
    };
    for (const std::string& name : root_.names()) {
      bool known = false;
      for (const auto& [key, section] : kSections) known = known || key == name;
      if (!known) {
        std::string list;
        for (const auto& [key, section] : kSections) list += (list.empty() ? "" : ", ") + std::string(key);
        root_.fail(name, fmt::format("unknown key '{}' in the scene (expected one of: {})", name, list));
      }
    }
    for (const auto& [key, section] : kSections) {
      if (root_.has(key)) (this->*section)(root_);
      if (key == "render" && options_.resolution)
        std::tie(out_.render.width, out_.render.height) = *options_.resolution;
    }
    assign_automatic_object_ids();
    return std::move(out_);
  }

  // Hash of everything the scene reads besides its own text (species files), for checkpoints and
  // golden headers.
  uint64_t dependency_hash() const { return dependency_hash_; }
  bool is_species_file(const std::filesystem::path& file) const { return species_.count(file.string()) > 0; }
  const std::map<std::string, Species>& species() const { return species_; }

 private:
  void parse_render(const Params& root) {
    const Params* t = root.table("render");
    t->check_keys({"width", "height", "spp", "seed", "max_depth", "bands", "quantity", "instancing", "isa"});
    RenderSettings& rs = out_.render;
    rs.width = static_cast<int>(t->integer("width", rs.width, 1, 65536));
    rs.height = static_cast<int>(t->integer("height", rs.height, 1, 65536));
    rs.spp = static_cast<int>(t->integer("spp", rs.spp, 1, 1 << 24));
    rs.seed = static_cast<uint64_t>(t->integer("seed", static_cast<int64_t>(rs.seed), 0, INT64_MAX));
    rs.integrator.max_depth = static_cast<int>(t->integer("max_depth", rs.integrator.max_depth, 1, 1024));
    if (t->has("bands")) {
      out_.bands = t->strings("bands");
      if (out_.bands.empty()) t->fail("bands", "'bands' needs at least one band, e.g. [\"rgb\", \"nir\"]");
      for (size_t i = 0; i < out_.bands.size(); ++i)
        for (size_t j = 0; j < i; ++j)
          if (out_.bands[i] == out_.bands[j]) t->fail("bands", "band '" + out_.bands[i] + "' is listed twice");
    }
    const std::string quantity = t->string("quantity", quantity_name(rs.quantity));
    if (quantity != "radiance" && quantity != "reflectance")
      t->fail("quantity", "quantity must be \"radiance\" or \"reflectance\"");
    rs.quantity = parse_quantity(quantity);
    if (t->has("isa")) {
      try {
        rs.isa = parse_embree_isa(t->string("isa", embree_isa_name(rs.isa)));
      } catch (const Error& e) {
        t->fail("isa", e.what());
      }
    }
    const std::string instancing = t->string("instancing", "auto");
    if (instancing == "auto")
      out_.scene.instance_level = InstanceLevel::automatic;
    else if (instancing == "native")
      out_.scene.instance_level = InstanceLevel::native;
    else if (instancing == "array")
      out_.scene.instance_level = InstanceLevel::array;
    else if (instancing == "sweep")
      out_.scene.instance_level = InstanceLevel::sweep;
    else
      t->fail("instancing", "instancing must be \"auto\", \"native\", \"array\" or \"sweep\"");
  }

  void parse_bands(const Params& root) {
    for (const Params* t : root.tables("bands")) {
      t->check_keys({"name", "response"});
      const std::string name = t->string("name");
      if (name.empty() || name.find_first_of(" .,") != std::string::npos)
        t->fail("name", "band name must be non-empty without spaces, dots or commas");
      if (!t->has("response")) t->fail("[[bands]] needs a response spectrum");
      const DenseSpectrum response = t->spectrum("response", Extrapolate::Zero);
      try {
        out_.custom_bands.push_back(make_srf_band(name, response));
      } catch (const ParseError&) {
        throw;
      } catch (const Error& e) {
        t->fail("response", e.what());
      }
    }
  }

  // [lod]: Weber & Penn §5 level of detail for the trees of [vegetation] and [[placements]]
  // (docs/lod.md), on when the table is present unless `enabled = false`; `bias` scales the ranges
  // at which detail drops (2 = twice as far). Parsed after [render] and [camera], whose image
  // height and field of view give each tree's calibrated range.
  void parse_lod(const Params& root) {
    const Params* t = root.table("lod");
    t->check_keys({"enabled", "bias"});
    lod_.enabled = t->boolean("enabled", true);
    lod_.bias = t->real("bias", 1.0, 1e-3, 1e3);
  }

  // [camera]: the view frame, and a projection from the registry (render/sensors/camera.h) that
  // reads its own parameters.
  void parse_camera(const Params& root) {
    const Params* t = root.table("camera");
    CameraDesc& c = out_.scene.camera;
    c.position = t->vec3("position", c.position);
    c.target = t->vec3("target", c.target);
    c.up = t->vec3("up", c.up);
    const std::string type = t->string("type", "perspective");
    std::optional<Projection> projection = create_registered<Projection>(type, *t);
    if (!projection)
      t->fail("type", fmt::format("camera type must be {}, not \"{}\"", registered_names<Projection>(), type));
    c.projection = *projection;
    // `above_terrain = true`: position and target z are heights above the [terrain] surface under
    // them (an eye-height camera on any terrain); applied once the terrain is built.
    camera_above_terrain_ = t->boolean("above_terrain", false);
    if (camera_above_terrain_ && !root.has("terrain")) t->fail("above_terrain", "above_terrain needs a [terrain]");
    t->check_unused();
    // Single-precision ray arithmetic: beyond this distance from the origin the view frame (and
    // every hit point) loses its precision; docs/limits.md.
    for (const char* key : {"position", "target"}) {
      const Vec3& v = key[0] == 'p' ? c.position : c.target;
      if (!(glm::max(glm::abs(v.x), glm::max(glm::abs(v.y), glm::abs(v.z))) <= kMaxSceneCoordinate_m))
        t->fail(key, fmt::format("camera {} must lie within {:g} m of the origin on every axis (docs/limits.md)", key,
                                 kMaxSceneCoordinate_m));
    }
    if (glm::length(c.target - c.position) <= 0) t->fail("camera position and target must differ");
    if (glm::length(glm::cross(glm::normalize(c.target - c.position), c.up)) < 1e-4f)
      t->fail("camera up must not be parallel to the view direction");
  }

  void parse_sun(const Params& root) {
    const Params* t = root.table("sun");
    t->check_keys({"enabled", "azimuth", "elevation", "angular_radius", "irradiance", "scale"});
    SunDesc& s = out_.scene.sun;
    s.enabled = t->boolean("enabled", true);
    s.azimuth_deg = t->real("azimuth", s.azimuth_deg, -360.0, 360.0);
    s.elevation_deg = t->real("elevation", s.elevation_deg, -90.0, 90.0);
    s.angular_radius_deg = t->real("angular_radius", s.angular_radius_deg, 1e-3, 10.0);
    if (t->has("irradiance")) s.irradiance = t->spectrum("irradiance", Extrapolate::Zero);
    s.irradiance *= t->real("scale", 1.0, 0.0, 1e6);
  }

  // [sky]: model = "none" or a registered sky model (render/lights/lights.h), which reads its own
  // parameters; spectrum, scale and ground_albedo apply to every model.
  void parse_sky(const Params& root) {
    const Params* t = root.table("sky");
    SkyDesc& s = out_.scene.sky;
    const std::string model = t->string("model", "cie");
    if (model == "none") {
      s.enabled = false;
    } else {
      std::optional<SkyModel> m = create_registered<SkyModel>(model, *t);
      if (!m) t->fail("model", fmt::format("sky model must be {} or \"none\"", registered_names<SkyModel>()));
      s.model = *m;
      s.spectrum = std::visit([](const auto& sky) { return sky.default_spectrum(); }, s.model);
    }
    if (t->has("spectrum")) s.spectrum = t->spectrum("spectrum", Extrapolate::Zero);
    s.spectrum *= t->real("scale", 1.0, 0.0, 1e6);
    s.ground_albedo = t->real("ground_albedo", 0.0, 0.0, 1.0);
    if (s.ground_albedo > 0 && !(s.enabled && upper_hemisphere_only(s.model)))
      t->fail("ground_albedo", "ground_albedo needs model = \"cie\" or \"preetham\"");
    t->check_unused();
  }

  // [haze]: an optional participating medium below `top` (render/media/haze.h). Its extinction at
  // 550 nm is given directly or as the meteorological visibility V (Koschmieder: σ = 3.912/V).
  void parse_haze(const Params& root) {
    const Params* t = root.table("haze");
    HazeDesc& h = out_.scene.haze;
    h.enabled = t->boolean("enabled", true);
    const std::string profile = t->string("profile", "homogeneous");
    if (profile == "homogeneous")
      h.profile = HazeProfile::Homogeneous;
    else if (profile == "exponential")
      h.profile = HazeProfile::Exponential;
    else
      t->fail("profile", "haze profile must be \"homogeneous\" or \"exponential\"");
    if (t->has("extinction") == t->has("visibility"))
      t->fail("[haze] needs exactly one of extinction (1/m at 550 nm) or visibility (m)");
    h.extinction_550 = t->has("extinction") ? t->real("extinction", 0.0, 0.0, 100.0)
                                            : static_cast<float>(3.912 / t->real("visibility", 1.0, 1.0, 1e7));
    h.angstrom = t->real("angstrom", h.angstrom, 0.0, 4.0);
    h.albedo = t->real("albedo", h.albedo, 0.0, 1.0);
    h.g = t->real("g", h.g, -0.99, 0.99);
    h.base_height = t->real("base_height", h.base_height, -1e5, 1e5);
    h.scale_height = t->real("scale_height", h.scale_height, 1.0, 1e5);
    const double top_default = h.profile == HazeProfile::Homogeneous ? 1000.0 : 1e30;
    const float top = t->real("top", top_default, -1e5, 1e30);
    h.top = top >= 1e30f ? std::numeric_limits<float>::infinity() : top;
    if (h.profile == HazeProfile::Homogeneous && !std::isfinite(h.top))
      t->fail("top", "a homogeneous haze needs a finite top (m)");
    t->check_unused();
  }

  // [materials.NAME] tables: the material registry (render/materials/material.h) picks the type and
  // the type reads its own parameters.
  void parse_materials(const Params& root) {
    const Params* t = root.table("materials");
    for (const std::string& name : t->names()) {
      const Params* m = t->table(name);
      if (material_ids_.count(name)) m->fail("material '" + name + "' is defined twice");
      material_ids_[name] =
          out_.scene.add_material(name, create_material(name, m->with_where("material '" + name + "'")));
    }
  }

  uint32_t material_ref(const Params& t, const char* key) {
    const std::string name = t.string(key);
    auto it = material_ids_.find(name);
    if (it == material_ids_.end()) {
      std::string known;
      for (const auto& [k, v] : material_ids_) known += (known.empty() ? "" : ", ") + k;
      t.fail(key, "unknown material '" + name + "' (defined: " + (known.empty() ? "none" : known) + ")");
    }
    return it->second;
  }

  // translate = [x,y,z], rotate = [rx,ry,rz] degrees (applied X, then Y, then Z), scale = s or [sx,sy,sz].
  static Mat4 transform(const Params& t) {
    const Vec3 translate = t.vec3("translate", Vec3(0.0f));
    const Vec3 rotate = t.vec3("rotate", Vec3(0.0f));
    Vec3 scale(1.0f);
    if (const ParamValue* s = t.get("scale")) {
      scale = s->is_number() ? Vec3(static_cast<float>(s->number())) : t.vec3("scale", scale);
      if (scale.x <= 0 || scale.y <= 0 || scale.z <= 0) t.fail("scale", "scale must be positive");
    }
    Mat4 m = glm::translate(Mat4(1.0f), translate);
    m = glm::rotate(m, radians(rotate.z), Vec3(0, 0, 1));
    m = glm::rotate(m, radians(rotate.y), Vec3(0, 1, 0));
    m = glm::rotate(m, radians(rotate.x), Vec3(1, 0, 0));
    return glm::scale(m, scale);
  }

  void parse_meshes(const Params& root) {
    for (const Params* t : root.tables("meshes")) {
      t->check_keys({"name",     "shape",     "file",   "material",    "size",       "radius",     "height",
                     "segments", "tiles",     "count",  "leaf_length", "leaf_width", "leaf_shape", "seed",
                     "radii",    "translate", "rotate", "scale",       "object_id",  "instances",  "tile"});
      Prototype p;
      p.name = t->string("name", fmt::format("mesh{}", out_.scene.prototypes.size()));
      const uint32_t material = material_ref(*t, "material");
      if (t->has("file")) {
        if (t->has("shape")) t->fail("give either shape or file, not both");
        p.triangles = read_mesh(t->file_path("file"));
        p.triangle_material = material;
      } else {
        make_shape(*t, p);
        (p.leaves.size() > 0 ? p.leaf_material : p.triangle_material) = material;
      }
      place(*t, out_.scene.add_prototype(std::move(p)));
    }
  }

  // The built-in shapes of [[meshes]], each reading its own keys. Adding a shape = one line here.
  static void make_shape(const Params& t, Prototype& p) {
    using Make = void (*)(const Params&, Prototype&);
    static constexpr std::pair<std::string_view, Make> kShapes[] = {
        {"plane",
         [](const Params& t, Prototype& p) {
           const Vec2 size = t.vec2("size", Vec2(10.0f));
           p.triangles = make_plane(size.x, size.y, static_cast<int>(t.integer("tiles", 1, 1, 4096)));
         }},
        {"box", [](const Params& t, Prototype& p) { p.triangles = make_box(t.vec3("size", Vec3(1.0f))); }},
        {"sphere",
         [](const Params& t, Prototype& p) {
           p.triangles =
               make_sphere(t.real("radius", 1.0, 1e-6, 1e6), static_cast<int>(t.integer("segments", 24, 3, 4096)));
         }},
        {"cylinder",
         [](const Params& t, Prototype& p) {
           p.triangles = make_cylinder(t.real("radius", 0.1, 1e-6, 1e6), t.real("height", 1.0, 1e-6, 1e6),
                                       static_cast<int>(t.integer("segments", 24, 3, 4096)));
         }},
        {"leaf_cloud",
         [](const Params& t, Prototype& p) {
           LeafCloudParams lc;
           lc.radii = t.vec3("radii", lc.radii);
           lc.count = static_cast<int>(t.integer("count", lc.count, 1, 50'000'000));
           lc.leaf_length_m = t.real("leaf_length", lc.leaf_length_m, 1e-4, 10.0);
           lc.leaf_width_m = t.real("leaf_width", lc.leaf_width_m, 1e-4, 10.0);
           const std::string ls = t.string("leaf_shape", "oval");
           const auto shape_id = leaf_shape_from_name(ls);
           if (!shape_id) t.fail("leaf_shape", "unknown leaf_shape '" + ls + "'");
           lc.shape = *shape_id;
           p.leaves = make_leaf_cloud(lc, static_cast<uint64_t>(t.integer("seed", 1, 0, INT64_MAX)));
         }},
    };
    const std::string shape = t.has("shape") ? t.string("shape") : std::string();
    for (const auto& [name, make] : kShapes)
      if (name == shape) return make(t, p);
    std::string list;
    for (size_t i = 0; i < std::size(kShapes); ++i)
      list += (i == 0 ? "" : i + 1 == std::size(kShapes) ? " or " : ", ") + std::string(kShapes[i].first);
    t.fail("shape", "shape must be " + list + " (or give file = \"mesh.obj|ply\")");
  }

  // Places instances of a prototype: `instances = [{translate, rotate, scale, object_id}, ...]` or
  // the table's own transform.
  // `tile = [nx, ny]` (odd counts) repeats every placed copy on an nx × ny grid centred on itself,
  // with the [plot]'s size as the spacing. `at` lists positions in the entry's own frame to place a
  // copy at (the spheres of a [[canopies]] entry); one copy at its origin by default.
  // `class_id` and `variant_id` label every copy (the `id.class` and `id.variant` AOVs).
  void place(const Params& t, uint32_t proto, uint32_t class_id = kClassMesh, uint32_t variant_id = 0,
             const std::vector<Vec3>& at = {Vec3(0.0f)}) {
    for (const Placed& c : placements(t, at))
      out_.scene.instances.push_back(Instance{proto, c.world_from_object, c.object_id, class_id, variant_id});
  }

  // Where a table's copies go: its transform, each of its `instances` (or itself), each tile of a
  // `tile`d plot, each offset in `at`, in that nesting order.
  struct Placed {
    Mat4 world_from_object;
    uint32_t object_id;
  };
  std::vector<Placed> placements(const Params& t, const std::vector<Vec3>& at = {Vec3(0.0f)}) {
    std::vector<Placed> out;
    const uint32_t object_id = static_cast<uint32_t>(t.integer("object_id", 0, 0, 1 << 24));
    const Mat4 base = transform(t);
    std::vector<Vec3> tiles{Vec3(0.0f)};
    if (t.has("tile")) {
      const std::vector<double> n = t.numbers("tile");
      if (n.size() != 2) t.fail("tile", "tile = [nx, ny] needs two counts");
      for (const double c : n)
        if (!(c >= 1 && c <= 99 && c == std::floor(c) && static_cast<int>(c) % 2 == 1))
          t.fail("tile", "tile counts must be odd whole numbers from 1 to 99 (the plot stays in the middle)");
      if (!out_.scene.plot.defined) t.fail("tile", "tile needs a [plot] with a size: the spacing of the copies");
      const Vec2 size = out_.scene.plot.hi - out_.scene.plot.lo;
      tiles.clear();
      const int nx = static_cast<int>(n[0]), ny = static_cast<int>(n[1]);
      for (int j = -(ny / 2); j <= ny / 2; ++j)
        for (int i = -(nx / 2); i <= nx / 2; ++i)
          tiles.emplace_back(static_cast<float>(i) * size.x, static_cast<float>(j) * size.y, 0.0f);
    }
    const auto put = [&](const Mat4& m, uint32_t id) {
      for (const Vec3& tile : tiles)
        for (const Vec3& a : at)
          out.push_back({glm::translate(Mat4(1.0f), tile) * m * glm::translate(Mat4(1.0f), a), id});
    };
    if (t.has("instances")) {
      for (const Params* it : t.tables("instances")) {
        it->check_keys({"translate", "rotate", "scale", "object_id"});
        put(transform(*it) * base, static_cast<uint32_t>(it->integer("object_id", object_id, 0, 1 << 24)));
      }
    } else {
      put(base, object_id);
    }
    return out;
  }

  // [plot]: the rectangle the plot sensor measures (size, centre), whether the world repeats it
  // (cyclic), the view directions, sample counts and the materials counted as ground.
  void parse_plot(const Params& root) {
    const Params* t = root.table("plot");
    t->check_keys({"size", "centre", "cyclic", "views", "principal_plane", "samples", "flux_samples", "ground"});
    PlotDesc& plot = out_.scene.plot;
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
    PlotSettings& ps = out_.plot;
    ps.samples = static_cast<int>(t->integer("samples", ps.samples, 1, 1 << 30));
    ps.flux_samples = static_cast<int>(t->integer("flux_samples", ps.flux_samples, 1, 1 << 30));
    if (const ParamValue* views = t->get("views")) {
      if (views->kind != ParamValue::Kind::Array) t->fail("views", "views = [[zenith, azimuth], ...] in degrees");
      for (const ParamValue& v : views->array) {
        if (v.kind != ParamValue::Kind::Array || v.array.size() != 2 || !v.array[0].is_number() ||
            !v.array[1].is_number())
          t->fail("views", "each view is [zenith, azimuth] in degrees");
        const double zenith = v.array[0].number(), azimuth = v.array[1].number();
        if (!(zenith >= 0 && zenith <= 89.9) || !(azimuth >= -360 && azimuth <= 360))
          t->fail("views", "view zenith must be in [0, 89.9] and azimuth in [-360, 360] degrees");
        ps.views.push_back(
            PlotView{static_cast<float>(zenith), static_cast<float>(azimuth), static_cast<float>(zenith)});
      }
    }
    if (t->has("principal_plane")) {
      const std::vector<double> pp = t->numbers("principal_plane");
      if (pp.size() != 3) t->fail("principal_plane", "principal_plane = [from, to, step] in degrees");
      try {
        const std::vector<PlotView> v = principal_plane_views(static_cast<float>(pp[0]), static_cast<float>(pp[1]),
                                                              static_cast<float>(pp[2]), out_.scene.sun.azimuth_deg);
        ps.views.insert(ps.views.end(), v.begin(), v.end());
      } catch (const Error& e) {
        t->fail("principal_plane", e.what());
      }
    }
    if (ps.views.size() > 100000) t->fail("views", "at most 100000 view directions");
    if (t->has("ground"))
      for (const std::string& name : t->strings("ground")) {
        auto it = material_ids_.find(name);
        if (it == material_ids_.end()) t->fail("ground", "unknown material '" + name + "'");
        ps.ground_materials.push_back(it->second);
      }
  }

  // [[leaves]]: leaf discs read from a RAMI leaf file (radius cx cy cz nx ny nz per row), one
  // prototype instanced like a mesh.
  void parse_leaves(const Params& root) {
    for (const Params* t : root.tables("leaves")) {
      t->check_keys({"name", "file", "material", "translate", "rotate", "scale", "object_id", "instances", "tile"});
      Prototype p;
      p.name = t->string("name", fmt::format("leaves{}", out_.scene.prototypes.size()));
      p.disc_material = material_ref(*t, "material");
      p.discs = read_leaf_discs(t->file_path("file"));
      place(*t, out_.scene.add_prototype(std::move(p)));
    }
  }

  // [[canopies]]: the RAMI abstract canopies, generated. type = "homogeneous" (a layer of discs over
  // a rectangle) or "spheres" (one sphere of discs instanced at each centre).
  void parse_canopies(const Params& root) {
    for (const Params* t : root.tables("canopies")) {
      t->check_keys({"name", "type", "material", "lai", "height", "size", "centre", "disc_radius", "leaf_angles",
                     "seed", "sphere_radius", "centres", "centres_file", "translate", "rotate", "scale", "object_id",
                     "instances", "tile"});
      const std::string type = t->string("type");
      Prototype p;
      p.name = t->string("name", fmt::format("canopy{}", out_.scene.prototypes.size()));
      p.disc_material = material_ref(*t, "material");
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
          for (const char* key : {"sphere_radius", "centres", "centres_file"})
            if (t->has(key)) t->fail(key, fmt::format("'{}' is for type = \"spheres\"", key));
          const PlotDesc& plot = out_.scene.plot;
          const Vec2 size = t->vec2("size", plot.defined ? plot.hi - plot.lo : Vec2(0.0f));
          if (!(size.x > 0 && size.y > 0))
            t->fail("size", "a homogeneous canopy needs size = [x, y] (or a [plot] to cover)");
          const Vec2 centre = t->vec2("centre", plot.defined ? 0.5f * (plot.lo + plot.hi) : Vec2(0.0f));
          p.discs = make_homogeneous_layer(centre - 0.5f * size, centre + 0.5f * size,
                                           static_cast<float>(t->real("height", 1.0, 1e-3, 1e4)),
                                           static_cast<float>(t->real("lai", 1.0, 1e-3, 100.0)), radius, angles, seed);
        } else if (type == "spheres") {
          for (const char* key : {"height", "size", "centre"})
            if (t->has(key)) t->fail(key, fmt::format("'{}' is for type = \"homogeneous\"", key));
          if (t->has("centres") == t->has("centres_file"))
            t->fail("spheres need either centres = [[x, y, z], ...] or centres_file, not both");
          if (t->has("centres_file")) {
            at = read_points(t->file_path("centres_file"));
          } else {
            const ParamValue* c = t->get("centres");
            at.clear();
            if (c->kind == ParamValue::Kind::Array)
              for (const ParamValue& v : c->array) {
                if (v.kind != ParamValue::Kind::Array || v.array.size() != 3) break;
                Vec3 q;
                for (int k = 0; k < 3; ++k)
                  q[k] = static_cast<float>(v.array[k].is_number() ? v.array[k].number() : NAN);
                if (!std::isfinite(q.x + q.y + q.z)) break;
                at.push_back(q);
              }
            if (at.empty() || (c->kind == ParamValue::Kind::Array && at.size() != c->array.size()))
              t->fail("centres", "centres = [[x, y, z], ...] in metres");
          }
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
      place(*t, out_.scene.add_prototype(std::move(p)), kClassMesh, 0, at);
    }
  }

  // The `id.class` of a name (a species or a target label): its row of the class table, added at
  // the end the first time (docs/scene_format.md, "Label AOVs").
  uint32_t class_of(const std::string& name) {
    std::vector<std::string>& names = out_.scene.class_names;
    for (size_t i = kFirstNamedClass; i < names.size(); ++i)
      if (names[i] == name) return static_cast<uint32_t>(i);
    names.push_back(name);
    return static_cast<uint32_t>(names.size() - 1);
  }

  // The `id.variant` of a generated tree or target mesh, by its key (a new row the first time).
  uint32_t variant_of(const std::string& key, VariantInfo info) {
    auto found = variant_ids_.find(key);
    if (found != variant_ids_.end()) return found->second;
    out_.variants.push_back(std::move(info));
    return variant_ids_[key] = static_cast<uint32_t>(out_.variants.size());
  }

  // Instances placed by [[placements]] and [[targets]] get object ids of their own: each recorded
  // range holds provisional ids 1, 2, ... (one per placed tree or target), moved here above every
  // id the file gives explicitly, in the order the ranges were placed.
  void assign_automatic_object_ids() {
    if (automatic_ranges_.empty()) return;
    const std::vector<Instance>& all = out_.scene.instances;
    uint64_t offset = 0;
    size_t pos = 0;
    for (const auto& [begin, end] : automatic_ranges_) {
      for (size_t i = pos; i < begin; ++i) offset = std::max<uint64_t>(offset, all[i].object_id);
      pos = end;
    }
    for (size_t i = pos; i < all.size(); ++i) offset = std::max<uint64_t>(offset, all[i].object_id);
    for (const auto& [begin, end] : automatic_ranges_) {
      uint32_t largest = 0;
      for (size_t i = begin; i < end; ++i) {
        Instance& inst = out_.scene.instances[i];
        largest = std::max(largest, inst.object_id);
        const uint64_t id = offset + inst.object_id;
        if (id > kMaxObjectId)
          root_.fail(
              fmt::format("more than {} labelled objects: object ids must stay exact in the float AOV "
                          "(docs/limits.md)",
                          kMaxObjectId));
        inst.object_id = static_cast<uint32_t>(id);
      }
      offset += largest;
    }
    for (TargetInfo& target : out_.targets) target.object_id = out_.scene.instances[target.instance].object_id;
  }

  // [[trees]]: a generated tree (species file + seed), meshed once per distinct (species, seed,
  // options, materials) and instanced. Leaves in material slot 0 take `leaf`, those in slots ≥ 1
  // (TREE-MAKER flowers and fruit) `flower`; each slot is its own prototype placed with the tree.
  // A TREE-MAKER species may omit `bark`, `leaf` and `flower`: its template's colours are used.
  void parse_trees(const Params& root) {
    for (const Params* t : root.tables("trees")) {
      t->check_keys({"name", "species", "seed", "bark", "dead_bark", "leaf", "flower", "leaves", "quality", "time",
                     "wind", "years", "translate", "rotate", "scale", "object_id", "instances", "tile"});
      const std::filesystem::path file = t->file_path("species");
      TreeOptions options;
      options.quality = t->real("quality", 1.0, 0.01, 100.0);
      options.time_s = t->real("time", 0.0, -1e9, 1e9);
      options.years = static_cast<int>(t->integer("years", 0, 0, 500));
      if (options_.time_s) options.time_s = *options_.time_s;
      const Vec2 wind = t->vec2("wind", Vec2(0.0f));
      if (wind.x < 0 || wind.y < 0) t->fail("wind", "wind = [speed, gust] must not be negative");
      options.wind_speed = wind.x;
      options.wind_gust = wind.y;
      const uint64_t seed = static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX));
      // `leaves = false`: the stems only (a bare tree, e.g. for a silhouette of the branching).
      const bool with_leaves = t->boolean("leaves", true);
      const Species& species = load_species_once(file);
      if (const auto* fg = std::get_if<FournierGrindalParams>(&species.model)) {
        place_solid_tree(*t, species, *fg, seed);
        continue;
      }
      const std::vector<uint32_t> materials = tree_materials(*t, species, with_leaves);
      std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}", file.string(), seed, options.quality, options.time_s,
                                    options.wind_speed, options.wind_gust, with_leaves);
      for (const uint32_t m : materials) key += fmt::format("|{}", m);
      if (options.years > 0) key += fmt::format("|years {}", options.years);
      if (t->has("dead_bark")) key += "|dead " + t->string("dead_bark");
      const auto generate = [&] {
        GeneratedTree tree = generate_tree(species, seed, options, with_leaves);
        if (!tree.error.empty()) t->fail(file.string() + ": " + tree.error);
        return tree;
      };
      std::optional<GeneratedTree> source;  // what the levels are made from (add_tree_prototypes consumes the tree)
      auto it = tree_prototypes_.find(key);
      if (it == tree_prototypes_.end()) {
        GeneratedTree tree = generate();
        if (lod_.enabled) source = lod_source(tree);
        it = tree_prototypes_.emplace(key, add_tree_prototypes(*t, t->string("name", species.name), tree, materials))
                 .first;
      }
      const uint32_t class_id = class_of(species.name);
      const uint32_t variant_id = variant_of(key, {"tree", species.name, file.string(), seed, class_id});
      if (!lod_.enabled) {
        for (const uint32_t proto : it->second) place(*t, proto, class_id, variant_id);
        continue;
      }
      // With [lod] (docs/lod.md): every copy at the level its own distance calls for, the levels
      // made once per tree (the same variant key as [[placements]] and [vegetation] use).
      const std::vector<Placed> copies = placements(*t);
      const Bounds3 object = prototypes_bounds(it->second);
      const size_t levels = kLodLevelR2.size();
      std::vector<uint8_t> level(copies.size()), used(levels, 0);
      for (size_t c = 0; c < copies.size(); ++c) {
        level[c] = static_cast<uint8_t>(lod_level_of(object, copies[c].world_from_object));
        used[level[c]] = tree_prototypes_.count(fmt::format("{}|lod {}", key, level[c])) == 0;
      }
      if (std::find(used.begin() + 1, used.end(), 1) != used.end()) {
        if (!source) source = lod_source(generate());
        for (LodJob& job : build_lod_levels(used, {*source}))
          tree_prototypes_.emplace(fmt::format("{}|lod {}", key, job.level),
                                   add_lod_prototypes(*t, t->string("name", species.name), job.lod, materials));
      }
      for (size_t c = 0; c < copies.size(); ++c) {
        const std::vector<uint32_t>& protos =
            level[c] == 0 ? it->second : tree_prototypes_.at(fmt::format("{}|lod {}", key, level[c]));
        for (const uint32_t proto : protos)
          out_.scene.instances.push_back(
              Instance{proto, copies[c].world_from_object, copies[c].object_id, class_id, variant_id});
      }
    }
  }

  // The object-space bounds of a tree's prototypes (stems, leaves, curves, discs).
  Bounds3 prototypes_bounds(const std::vector<uint32_t>& protos) const {
    Bounds3 b;
    for (const uint32_t id : protos) {
      const Prototype& p = out_.scene.prototypes[id];
      for (const Vec3& v : p.triangles.positions) b.extend(v);
      for (const Vec3& v : p.leaves.corners) b.extend(v);
      for (const Vec4& v : p.curves.points) b.extend(Vec3(v));
      for (size_t i = 0; i < p.discs.size(); ++i) b.extend(p.discs.centre[i]);
    }
    return b;
  }

  // [[placements]]: trees from a placement list (a CSV `file`, scenes/placement_list.h, or TOML
  // `rows`), each row x, y, species, seed, scale, heading and optional z. `species` maps the
  // rows' species names to species files and their materials. Every distinct (species, seed) is
  // generated once, in parallel, and added in the order first listed; each row is one instance per
  // prototype of its variant with an object id of its own.
  void parse_placements(const Params& root) {
    for (const Params* t : root.tables("placements")) {
      t->check_keys({"file", "rows", "species"});
      if (t->has("file") == t->has("rows")) t->fail("[[placements]] needs either file = \"list.csv\" or rows = [...]");
      const Params* kinds_table = t->table("species");
      struct Kind {
        std::string name;
        const Params* table = nullptr;
        const Species* species = nullptr;
        std::filesystem::path file;
        TreeOptions options;
        bool with_leaves = true;
        std::vector<uint32_t> materials;
        uint32_t class_id = 0;
      };
      std::vector<Kind> kinds;
      for (const std::string& name : kinds_table->names()) {
        const Params* k = kinds_table->table(name);
        k->check_keys({"species", "bark", "dead_bark", "leaf", "flower", "leaves", "quality"});
        Kind kind;
        kind.name = name;
        kind.table = k;
        kind.file = k->file_path("species");
        kind.species = &load_species_once(kind.file);
        if (std::holds_alternative<FournierGrindalParams>(kind.species->model))
          k->fail("species",
                  "a Fournier-Grindal species (solids) is placed with [[trees]]; placement lists take "
                  "meshed species");
        kind.options.quality = k->real("quality", 1.0, 0.01, 100.0);
        if (options_.time_s) kind.options.time_s = *options_.time_s;
        kind.with_leaves = k->boolean("leaves", true);
        kind.materials = tree_materials(*k, *kind.species, kind.with_leaves);
        kind.class_id = class_of(kind.species->name);
        kinds.push_back(std::move(kind));
      }
      if (kinds.empty()) kinds_table->fail("[placements.species] needs at least one species: NAME = { species = ... }");

      // The rows, compactly; variants keyed by (kind, seed) in first-listed order.
      struct Row {
        float x, y, z, scale, heading_deg;
        uint32_t variant;
      };
      std::vector<Row> rows;
      std::vector<std::pair<uint32_t, uint64_t>> variants;
      std::map<std::pair<uint32_t, uint64_t>, uint32_t> variant_index;
      const auto add_row = [&](const PlacementRow& r, const std::function<void(const std::string&)>& fail) {
        uint32_t kind = 0;
        while (kind < kinds.size() && kinds[kind].name != r.species) ++kind;
        if (kind == kinds.size()) {
          std::string known;
          for (const Kind& k : kinds) known += (known.empty() ? "" : ", ") + k.name;
          fail(fmt::format("unknown species '{}' (the [[placements]] entry names: {})", r.species, known));
        }
        auto [it, added] = variant_index.emplace(std::make_pair(kind, r.seed), static_cast<uint32_t>(variants.size()));
        if (added) variants.emplace_back(kind, r.seed);
        rows.push_back(Row{r.x, r.y, r.z, r.scale, r.heading_deg, it->second});
      };
      if (t->has("file")) {
        const std::filesystem::path list = t->file_path("file");
        for_each_placement_row(list, kMaxSceneCoordinate_m, [&](const PlacementRow& r, int line) {
          add_row(r, [&](const std::string& what) { throw ParseError(list, line, what); });
        });
      } else {
        for (const Params* r : t->tables("rows")) {
          r->check_keys({"x", "y", "z", "species", "seed", "scale", "heading"});
          const double m = kMaxSceneCoordinate_m;
          const std::string species = r->string("species");
          PlacementRow row;
          row.x = static_cast<float>(r->number("x", 0.0, -m, m));
          row.y = static_cast<float>(r->number("y", 0.0, -m, m));
          row.z = static_cast<float>(r->number("z", 0.0, -m, m));
          if (!r->has("x") || !r->has("y")) r->fail("a placement row needs x and y");
          row.species = species;
          row.seed = static_cast<uint64_t>(r->integer("seed", 1, 0, INT64_MAX));
          row.scale = r->real("scale", 1.0, 1e-6, 1e4);
          row.heading_deg = r->real("heading", 0.0, -3600.0, 3600.0);
          add_row(row, [&](const std::string& what) { r->fail("species", what); });
        }
      }

      // Every variant generated once, in parallel; prototypes added in the order first listed.
      std::vector<GeneratedTree> generated(variants.size());
      tbb::parallel_for(size_t{0}, variants.size(), [&](size_t v) {
        const Kind& kind = kinds[variants[v].first];
        generated[v] = generate_tree(*kind.species, variants[v].second, kind.options, kind.with_leaves);
      });
      std::vector<std::vector<uint32_t>> variant_protos(variants.size());
      std::vector<uint32_t> variant_ids(variants.size());
      std::vector<std::string> variant_keys(variants.size());
      std::vector<Bounds3> variant_bounds(variants.size());
      std::vector<GeneratedTree> lod_sources(lod_.enabled ? variants.size() : 0);  // kept for the levels
      for (size_t v = 0; v < variants.size(); ++v) {
        const Kind& kind = kinds[variants[v].first];
        const uint64_t seed = variants[v].second;
        if (!generated[v].error.empty())
          kind.table->fail("species", fmt::format("{} (seed {}): {}", kind.file.string(), seed, generated[v].error));
        std::string key =
            fmt::format("{}|{}|{}|{}|{}|{}|{}", kind.file.string(), seed, kind.options.quality, kind.options.time_s,
                        kind.options.wind_speed, kind.options.wind_gust, kind.with_leaves);
        for (const uint32_t m : kind.materials) key += fmt::format("|{}", m);
        if (kind.table->has("dead_bark")) key += "|dead " + kind.table->string("dead_bark");
        if (lod_.enabled) {
          variant_bounds[v] = bounds_of(generated[v].mesh);
          lod_sources[v] = lod_source(generated[v]);
        }
        auto it = tree_prototypes_.find(key);
        if (it == tree_prototypes_.end())
          it = tree_prototypes_
                   .emplace(key, add_tree_prototypes(*kind.table, kind.species->name, generated[v], kind.materials))
                   .first;
        generated[v] = GeneratedTree{};
        variant_keys[v] = key;
        variant_protos[v] = it->second;
        variant_ids[v] = variant_of(key, {"tree", kind.species->name, kind.file.string(), seed, kind.class_id});
      }

      const auto placed = [](const Row& r) {
        const float heading = radians(r.heading_deg);
        const float c = std::cos(heading) * r.scale, sn = std::sin(heading) * r.scale;
        // Translate · rotate by −heading about Z (a compass bearing turns clockwise) · scale.
        Mat4 m(1.0f);
        m[0] = Vec4(c, -sn, 0.0f, 0.0f);
        m[1] = Vec4(sn, c, 0.0f, 0.0f);
        m[2] = Vec4(0.0f, 0.0f, r.scale, 0.0f);
        m[3] = Vec4(r.x, r.y, r.z, 1.0f);
        return m;
      };
      // With [lod], each row's level (docs/lod.md); a level's prototypes are added once, when
      // first used, in variant then level order (so independent of the thread count).
      const size_t levels = kLodLevelR2.size();
      std::vector<uint8_t> row_level(lod_.enabled ? rows.size() : 0, 0);
      std::vector<uint8_t> used(variants.size() * levels, 0);
      for (size_t i = 0; i < row_level.size(); ++i) {
        row_level[i] = static_cast<uint8_t>(lod_level_of(variant_bounds[rows[i].variant], placed(rows[i])));
        used[rows[i].variant * levels + row_level[i]] = 1;
      }
      std::vector<std::vector<uint32_t>> level_protos(variants.size() * levels);
      for (size_t v = 0; v < variants.size(); ++v) level_protos[v * levels] = variant_protos[v];
      for (size_t v = 0; v < variants.size(); ++v)
        for (size_t k = 1; k < levels; ++k)
          if (tree_prototypes_.count(fmt::format("{}|lod {}", variant_keys[v], k))) used[v * levels + k] = 0;
      for (LodJob& job : build_lod_levels(used, lod_sources)) {
        const Kind& kind = kinds[variants[job.variant].first];
        tree_prototypes_.emplace(fmt::format("{}|lod {}", variant_keys[job.variant], job.level),
                                 add_lod_prototypes(*kind.table, kind.species->name, job.lod, kind.materials));
      }
      lod_sources.clear();
      for (size_t v = 0; v < variants.size(); ++v)
        for (size_t k = 1; k < levels; ++k) {
          auto it = tree_prototypes_.find(fmt::format("{}|lod {}", variant_keys[v], k));
          if (it != tree_prototypes_.end()) level_protos[v * levels + k] = it->second;
        }

      std::vector<Instance>& instances = out_.scene.instances;
      const size_t first = instances.size();
      size_t count = 0;
      for (size_t i = 0; i < rows.size(); ++i)
        count += level_protos[rows[i].variant * levels + (row_level.empty() ? 0 : row_level[i])].size();
      instances.reserve(first + count);
      uint32_t object = 0;
      for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        ++object;
        const Mat4 m = placed(r);
        const Kind& kind = kinds[variants[r.variant].first];
        for (const uint32_t proto : level_protos[r.variant * levels + (row_level.empty() ? 0 : row_level[i])])
          instances.push_back(Instance{proto, m, object, kind.class_id, variant_ids[r.variant]});
      }
      if (object > kMaxObjectId) t->fail(fmt::format("more than {} placed trees", kMaxObjectId));
      automatic_ranges_.emplace_back(first, instances.size());
    }
  }

  // [[targets]]: a mesh (OBJ/PLY) for detection studies, placed by position, heading and scale,
  // with a class `label` and a material; `ground = "snap"` (default) puts its lowest point on the
  // highest ground (the [[meshes]] and terrain placed so far) under its footprint's centre and
  // corners (geometry/ground.h). Each target gets an object id of its own.
  void parse_targets(const Params& root) {
    for (const Params* t : root.tables("targets")) {
      t->check_keys({"name", "file", "material", "label", "position", "heading", "scale", "ground"});
      const std::filesystem::path file = t->file_path("file");
      const uint32_t material = material_ref(*t, "material");
      const std::string label = t->string("label");
      if (label.empty()) t->fail("label", "label must name the target's class, e.g. \"vehicle\"");
      if (!t->has("position")) t->fail("[[targets]] needs position = [x, y, z]");
      const Vec3 position = t->vec3("position", Vec3(0.0f));
      for (int i = 0; i < 3; ++i)
        if (!(std::abs(position[i]) <= kMaxSceneCoordinate_m))
          t->fail("position", fmt::format("position must lie within {:g} m of the origin", kMaxSceneCoordinate_m));
      const float heading_deg = t->real("heading", 0.0, -3600.0, 3600.0);
      const float scale = t->real("scale", 1.0, 1e-6, 1e6);
      const std::string ground = t->string("ground", "snap");
      if (ground != "snap" && ground != "none") t->fail("ground", "ground must be \"snap\" or \"none\"");
      const std::string key = fmt::format("{}|{}", file.string(), material);
      auto it = target_prototypes_.find(key);
      if (it == target_prototypes_.end()) {
        Prototype p;
        p.name = file.filename().string();
        p.triangles = read_mesh(file);
        if (p.triangles.triangles.empty()) t->fail("file", file.string() + ": the mesh has no triangles");
        p.triangle_material = material;
        it = target_prototypes_.emplace(key, out_.scene.add_prototype(std::move(p))).first;
      }
      const uint32_t proto = it->second;
      const uint32_t class_id = class_of(label);
      const uint32_t variant_id =
          variant_of("target|" + key, {"target", out_.scene.prototypes[proto].name, file.string(), 0, class_id});
      const float heading = radians(heading_deg);
      const auto placed = [&](float z) {
        Mat4 m = glm::translate(Mat4(1.0f), Vec3(position.x, position.y, z));
        m = glm::rotate(m, -heading, Vec3(0, 0, 1));
        return glm::scale(m, Vec3(scale));
      };
      float z = position.z;
      if (ground == "snap") {
        const TriangleMesh& mesh = out_.scene.prototypes[proto].triangles;
        const Bounds3 at_zero = placed_bounds(mesh, placed(0.0f));
        const std::optional<float> h = ground_height_under(at_zero);
        if (!h)
          t->fail("ground", fmt::format("nothing to snap to under the target at ({:g}, {:g}): no [[meshes]] or "
                                        "terrain there (or give ground = \"none\")",
                                        position.x, position.y));
        z = *h - at_zero.lo.z;
      }
      TargetInfo info;
      info.name = t->string("name", fmt::format("target{}", out_.targets.size() + 1));
      info.instance = static_cast<uint32_t>(out_.scene.instances.size());
      info.class_id = class_id;
      info.variant_id = variant_id;
      info.position = Vec3(position.x, position.y, z);
      info.heading_deg = heading_deg;
      out_.scene.instances.push_back(Instance{proto, placed(z), 1, class_id, variant_id});
      automatic_ranges_.emplace_back(info.instance, info.instance + 1);
      out_.targets.push_back(std::move(info));
    }
  }

  // The ground under a footprint: the highest surface of the ground meshes ([[meshes]] and terrain:
  // classes kClassMesh and kClassTerrain) on the vertical lines through the centre and the four
  // corners of `footprint` (x and y), or nullopt if none meets them.
  std::optional<float> ground_height_under(const Bounds3& footprint) {
    if (!ground_made_) {
      for (const Instance& inst : out_.scene.instances) {
        if (inst.class_id != kClassMesh && inst.class_id != kClassTerrain) continue;
        const TriangleMesh& mesh = out_.scene.prototypes[inst.prototype].triangles;
        if (mesh.triangles.empty()) continue;
        ground_.push_back(PlacedMesh{&mesh, inst.world_from_object, placed_bounds(mesh, inst.world_from_object)});
      }
      ground_made_ = true;
    }
    const Vec2 lo(footprint.lo), hi(footprint.hi);
    std::optional<float> best;
    for (const Vec2 xy : {(lo + hi) * 0.5f, lo, hi, Vec2(lo.x, hi.y), Vec2(hi.x, lo.y)}) {
      const std::optional<float> h = highest_surface_z(ground_, xy);
      if (h && (!best || *h > *best)) best = h;
    }
    return best;
  }

  // The prototypes of a generated tree: stems with the first leaf material slot, one more per
  // further slot with leaves, and the dead branches (the table's `dead_bark`, else darker bark).
  std::vector<uint32_t> add_tree_prototypes(const Params& t, const std::string& name, GeneratedTree& tree,
                                            const std::vector<uint32_t>& materials) {
    std::vector<uint32_t> protos;
    Prototype p;
    p.name = name;
    p.triangles = std::move(tree.mesh.stems);
    p.triangle_material = materials[0];
    for (size_t slot = 0; slot + 1 < materials.size(); ++slot) {
      LeafQuads quads = leaves_in_slot(tree.mesh.leaves, tree.model.leaves, slot, materials.size() - 2);
      if (slot > 0 && quads.size() == 0) continue;
      p.leaves = std::move(quads);
      p.leaf_material = materials[slot + 1];
      protos.push_back(out_.scene.add_prototype(std::move(p)));
      p = Prototype{};
      p.name = fmt::format("{} (leaf material {})", name, slot + 1);
    }
    if (!tree.mesh.dead_stems.triangles.empty()) {
      Prototype dead;
      dead.name = name + " (dead branches)";
      dead.triangles = std::move(tree.mesh.dead_stems);
      dead.triangle_material = t.has("dead_bark") ? material_ref(t, "dead_bark") : darker_bark(materials[0]);
      protos.push_back(out_.scene.add_prototype(std::move(dead)));
    }
    tree.model = TreeModel{};
    return protos;
  }

  // The prototypes of one level of detail of a generated tree (lod_prototypes), in the layout of
  // add_tree_prototypes; dead branches take the table's `dead_bark`, else darker bark.
  std::vector<uint32_t> add_lod_prototypes(const Params& t, const std::string& name, TreeLod& level,
                                           const std::vector<uint32_t>& materials) {
    const bool dead = !level.mesh.dead_stems.triangles.empty() || level.dead_lines.size() > 0;
    const uint32_t dead_material = !dead                ? materials[0]
                                   : t.has("dead_bark") ? material_ref(t, "dead_bark")
                                                        : darker_bark(materials[0]);
    std::vector<uint32_t> ids;
    for (Prototype& p : lod_prototypes(name, level, materials, dead_material))
      ids.push_back(out_.scene.add_prototype(std::move(p)));
    return ids;
  }

  // The level of detail of a tree placed by `world_from_object` (0 = full; 0 without [lod]).
  int lod_level_of(const Bounds3& object, const Mat4& world_from_object) const {
    return instance_lod_level(lod_, out_.scene.camera, out_.render.width, out_.render.height,
                              transformed(object, world_from_object));
  }

  // A Fournier–Grindal tree: one prototype holding its solids (trunk, crown), made once per
  // (species, seed, materials). `bark` and `leaf` are optional: without them the species' §5 bark
  // palette and §4 crown palette become diffuse reflectances (Smits up-sampling), the paper's
  // opaque textured surface.
  void place_solid_tree(const Params& t, const Species& species, const FournierGrindalParams& fg, uint64_t seed) {
    if (t.has("flower")) t.fail("flower", "'flower' is for models with flowers (TREE-MAKER templates)");
    if (t.has("dead_bark")) t.fail("dead_bark", "'dead_bark' is for models with dead branches");
    const auto palette = [&](const char* key, const std::string& what, const std::vector<Vec3>& rgb) {
      if (t.has(key)) return std::vector<uint32_t>{material_ref(t, key)};
      std::vector<uint32_t> ids;
      for (size_t i = 0; i < rgb.size(); ++i) {
        const std::string name = fmt::format("{} {} colour {} ({:.3f}, {:.3f}, {:.3f})", species.file.string(), what, i,
                                             rgb[i].x, rgb[i].y, rgb[i].z);
        auto found = material_ids_.find(name);
        if (found == material_ids_.end())
          found =
              material_ids_.emplace(name, out_.scene.add_material(name, make_diffuse(name, rgb_to_reflectance(rgb[i]))))
                  .first;
        ids.push_back(found->second);
      }
      return ids;
    };
    const std::vector<uint32_t> bark = palette("bark", "bark", fournier_grindal_bark_palette(fg, seed));
    if (fg.leaf_area_density > 0.0f && !t.has("leaf"))
      t.fail("a turbid crown (optics = \"turbid\") needs 'leaf': the leaves' reflectance and transmittance");
    const std::vector<uint32_t> crown = palette("leaf", "crown", fg.crown_rgb);
    std::string key = fmt::format("{}|{}|solids", species.file.string(), seed);
    for (const uint32_t m : bark) key += fmt::format("|{}", m);
    for (const uint32_t m : crown) key += fmt::format("|c{}", m);
    auto it = tree_prototypes_.find(key);
    if (it == tree_prototypes_.end()) {
      Prototype p;
      p.name = t.string("name", species.name);
      try {
        p.solids = make_tree(fg, seed, TreeOptions{}).solids;
      } catch (const Error& e) {
        t.fail(species.file.string() + ": " + e.what());
      }
      for (const HalfSpaceSolid& solid : p.solids) p.solid_palettes.push_back(solid.material_slot == 0 ? bark : crown);
      it = tree_prototypes_.emplace(key, std::vector<uint32_t>{out_.scene.add_prototype(std::move(p))}).first;
    }
    const uint32_t class_id = class_of(species.name);
    const uint32_t variant_id = variant_of(key, {"tree", species.name, species.file.string(), seed, class_id});
    for (const uint32_t proto : it->second) place(t, proto, class_id, variant_id);
  }

  // Dead branches' bark when the scene names none: a copy of `bark` with its reflectance halved
  // (docs/scene_format.md), made once per bark material.
  uint32_t darker_bark(uint32_t bark) {
    const std::string name = out_.scene.material_names[bark] + " (dead, reflectance x0.5)";
    auto found = material_ids_.find(name);
    if (found != material_ids_.end()) return found->second;
    Material m = scaled_reflectance(out_.scene.materials[bark], kDeadBarkReflectanceScale);
    const uint32_t id = out_.scene.add_material(name, std::move(m));
    return material_ids_[name] = id;
  }

  // A tree's materials: bark, then one per leaf material slot. Named ones come from the scene; a
  // TREE-MAKER species fills what the scene leaves out with its template's colours (docs/treemaker.md:
  // Smits up-sampling; bark diffuse, elements opaque two-sided leaves). Other models need `bark`
  // and `leaf`; `flower` is then unused.
  // A tree drawn without leaves (`leaves = false`) may leave out `leaf`.
  std::vector<uint32_t> tree_materials(const Params& t, const Species& species, bool with_leaves) {
    const TreeMakerTemplate* tm = std::get_if<TreeMakerTemplate>(&species.model);
    if (tm == nullptr) {
      if (t.has("flower")) t.fail("flower", "'flower' is for models with flowers (TREE-MAKER templates)");
      const uint32_t bark = material_ref(t, "bark");
      return {bark, with_leaves || t.has("leaf") ? material_ref(t, "leaf") : bark};
    }
    const TreeMakerMaterials colours = treemaker_materials(*tm);
    const auto from_template = [&](const std::string& what, bool leaf, const Vec3& rgb) {
      const std::string name = fmt::format("{} {} (template colour)", species.file.string(), what);
      auto found = material_ids_.find(name);
      if (found != material_ids_.end()) return found->second;
      const DenseSpectrum rho = rgb_to_reflectance(rgb);
      const uint32_t id = out_.scene.add_material(
          name, leaf ? Material(make_leaf(name, rho, DenseSpectrum())) : Material(make_diffuse(name, rho)));
      return material_ids_[name] = id;
    };
    std::vector<uint32_t> out;
    out.push_back(t.has("bark") ? material_ref(t, "bark") : from_template("bark", false, colours.bark_rgb));
    for (size_t slot = 0; slot < std::max<size_t>(colours.element_rgb.size(), 1); ++slot) {
      const char* key = slot == 0 ? "leaf" : "flower";
      if (t.has(key)) {
        out.push_back(material_ref(t, key));
        if (slot > 0) break;  // a named flower material takes every slot beyond the leaves
      } else {
        const Vec3 rgb = slot < colours.element_rgb.size() ? colours.element_rgb[slot] : Vec3(0.5f);
        const std::string what = slot < colours.element_color_names.size() ? colours.element_color_names[slot] : "leaf";
        out.push_back(from_template(what, true, rgb));
      }
    }
    return out;
  }

  const Species& load_species_once(const std::filesystem::path& file) {
    auto sp = species_.find(file.string());
    if (sp == species_.end()) {
      const std::string text = read_input_file(file, kMaxSpeciesFileBytes, "species file");
      dependency_hash_ = hash_ids(dependency_hash_, hash_text(text));
      sp = species_.emplace(file.string(), parse_species(text, file)).first;
      out_.warnings.insert(out_.warnings.end(), sp->second.warnings.begin(), sp->second.warnings.end());
      // A TOML species naming a TREE-MAKER template depends on the template's text too.
      const auto* tm = std::get_if<TreeMakerTemplate>(&sp->second.model);
      if (tm != nullptr && tm->source != file) {
        dependency_hash_ =
            hash_ids(dependency_hash_, hash_text(read_input_file(tm->source, kMaxSpeciesFileBytes, "template file")));
      }
    }
    return sp->second;
  }

  // [terrain]: an elevation raster (any one-channel image OpenImageIO reads, 16-bit integer or
  // float) or a procedural fBm/ridged terrain, meshed once (geometry/terrain.h) with smooth normals.
  void parse_terrain(const Params& root) {
    const Params* t = root.table("terrain");
    t->check_keys({"file", "metres_per_pixel", "vertical_scale", "height_offset", "origin", "step", "material",
                   "object_id", "size", "centre", "resolution", "relief", "feature_size", "octaves", "gain", "noise",
                   "seed"});
    const uint32_t material = material_ref(*t, "material");
    const int step = static_cast<int>(t->integer("step", 1, 1, 4096));
    if (t->has("file")) {
      for (const char* key :
           {"size", "centre", "resolution", "relief", "feature_size", "octaves", "gain", "noise", "seed"})
        if (t->has(key)) t->fail(key, fmt::format("'{}' is for a procedural terrain (one without 'file')", key));
      ElevationRaster er;
      er.metres_per_pixel = t->real("metres_per_pixel", 1.0, 1e-3, 1e5);
      er.vertical_scale = t->real("vertical_scale", 1.0, 0.0, 1e5);
      er.height_offset_m = t->real("height_offset", 0.0, -1e5, 1e5);
      if (t->has("origin")) er.origin_m = t->vec2("origin", Vec2(0.0f));
      er.step = step;
      try {
        terrain_ = read_elevation_raster(t->file_path("file"), er, &extent_min_, &extent_max_);
      } catch (const ParseError&) {
        throw;
      } catch (const Error& e) {
        t->fail("file", e.what());
      }
    } else {
      for (const char* key : {"metres_per_pixel", "vertical_scale", "height_offset", "origin"})
        if (t->has(key)) t->fail(key, fmt::format("'{}' is for a terrain from a raster ('file')", key));
      ProceduralTerrainParams pt;
      pt.size_m = t->vec2("size", pt.size_m);
      if (!(pt.size_m.x > 0 && pt.size_m.y > 0 && pt.size_m.x <= 1e6f && pt.size_m.y <= 1e6f))
        t->fail("size", "size = [x, y] must be positive metres, at most 1e6");
      pt.centre_m = t->vec2("centre", pt.centre_m);
      pt.resolution_m = t->real("resolution", pt.resolution_m, 1e-3, 1e5) * static_cast<float>(step);
      pt.relief_m = t->real("relief", pt.relief_m, 0.0, 1e5);
      pt.feature_size_m = t->real("feature_size", pt.feature_size_m, 1e-2, 1e7);
      pt.octaves = static_cast<int>(t->integer("octaves", pt.octaves, 1, 16));
      pt.gain = t->real("gain", pt.gain, 0.0, 1.0);
      const std::string noise = t->string("noise", "fbm");
      if (noise != "fbm" && noise != "ridged") t->fail("noise", "noise must be \"fbm\" or \"ridged\"");
      pt.ridged = noise == "ridged";
      pt.seed = static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX));
      if (static_cast<double>(pt.size_m.x / pt.resolution_m) * static_cast<double>(pt.size_m.y / pt.resolution_m) >
          kMaxTerrainNodes)
        t->fail("resolution",
                fmt::format("the terrain would have more than {:g} nodes: raise resolution or step", kMaxTerrainNodes));
      terrain_ = make_procedural_terrain(pt);
      extent_min_ = pt.centre_m - 0.5f * pt.size_m;
      extent_max_ = pt.centre_m + 0.5f * pt.size_m;
    }
    if (static_cast<double>(terrain_->width) * terrain_->height > kMaxTerrainNodes)
      t->fail("step", fmt::format("the terrain has {} x {} nodes, more than {:g}: raise step", terrain_->width,
                                  terrain_->height, kMaxTerrainNodes));
    if (camera_above_terrain_) {
      CameraDesc& c = out_.scene.camera;
      c.position.z += terrain_height(*terrain_, Vec2(c.position));
      c.target.z += terrain_height(*terrain_, Vec2(c.target));
    }
    Prototype p;
    p.name = "terrain";
    p.triangles = make_terrain_mesh(*terrain_);
    p.triangle_material = material;
    out_.scene.instances.push_back(Instance{out_.scene.add_prototype(std::move(p)), Mat4(1.0f),
                                            static_cast<uint32_t>(t->integer("object_id", 0, 0, 1 << 24)),
                                            kClassTerrain, 0});
  }

  // [[grass]]: up to three grass types (feature-map grass bits 1–3, in order), each a patch of
  // curved blades made once (geometry/grass.h) and instanced by [vegetation].
  void parse_grass(const Params& root) {
    const std::vector<const Params*> tables = root.tables("grass");
    for (const Params* t : tables) {
      if (grass_.size() == kFeatureGrassTypes)
        t->fail("at most 3 [[grass]] types (a feature map's 2 grass bits choose one of 3)");
      t->check_keys({"name", "material", "density", "length", "width", "bend", "patch_size", "seed", "trace"});
      GrassParams g;
      g.density_per_m2 = t->real("density", g.density_per_m2, 0.0, 1e5);
      g.length_m = range(*t, "length", g.length_m, 1e-3, 10.0);
      g.width_m = t->real("width", g.width_m, 1e-5, 1.0);
      g.bend = t->real("bend", g.bend, 0.0, 1.0);
      g.patch_size_m = t->real("patch_size", g.patch_size_m, 0.1, 100.0);
      Prototype p;
      p.name = t->string("name", fmt::format("grass {}", grass_.size() + 1));
      p.curve_material = material_ref(*t, "material");
      try {
        p.curves = make_grass_patch(g, static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX)));
      } catch (const Error& e) {
        t->fail("density", e.what());
      }
      const std::string trace = t->string("trace", "strips");
      if (trace != "strips" && trace != "curves") t->fail("trace", "trace must be \"strips\" or \"curves\"");
      p.curves.exact = trace == "curves";
      grass_.push_back({out_.scene.add_prototype(std::move(p)), g.patch_size_m});
    }
  }

  // `key = x` or `key = [lo, hi]` (lo <= hi) within [lo_limit, hi_limit].
  static Vec2 range(const Params& t, const char* key, Vec2 fallback, double lo_limit, double hi_limit) {
    const ParamValue* v = t.get(key);
    if (v == nullptr) return fallback;
    const Vec2 r = v->is_number() ? Vec2(t.real(key, 0.0, lo_limit, hi_limit)) : t.vec2(key, fallback);
    if (!(r.x >= lo_limit && r.y <= hi_limit && r.x <= r.y))
      t.fail(key, fmt::format("{} = [min, max] needs {:g} <= min <= max <= {:g}", key, lo_limit, hi_limit));
    return r;
  }

  // [vegetation]: trees and grass over the terrain from a 16-bit feature map (Weber & Penn §6,
  // plates 3–4): [[vegetation.species]] name a species file per bit 0–13 with a density, minimum
  // spacing, variants (seeds) and scale range; the top two bits choose a [[grass]] type. Every
  // variant is generated once, in parallel, and instanced; each placed tree gets its own object id.
  void parse_vegetation(const Params& root) {
    const Params* t = root.table("vegetation");
    t->check_keys({"feature_map", "seed", "first_object_id", "feature_resolution", "patch_size", "tree_cover",
                   "grass_cover", "species"});
    if (!terrain_) t->fail("[vegetation] needs a [terrain] to place on");
    const uint64_t seed = static_cast<uint64_t>(t->integer("seed", 1, 0, INT64_MAX));
    const std::vector<const Params*> entries = t->has("species") ? t->tables("species") : std::vector<const Params*>{};
    struct Variant {
      size_t entry = 0;
      uint64_t seed = 0;
      GeneratedTree tree;
      Bounds3 bounds;  // with [lod]
    };
    std::vector<SpeciesPlacement> rules;
    std::vector<Variant> variants;
    std::vector<const Species*> species;
    std::vector<TreeOptions> options;
    std::vector<std::vector<uint32_t>> materials;
    uint32_t bits_used = 0;
    for (const Params* e : entries) {
      e->check_keys({"bit", "species", "name", "seed", "bark", "leaf", "dead_bark", "quality", "density", "min_spacing",
                     "variants", "scale"});
      if (!e->has("bit")) e->fail("[[vegetation.species]] needs bit = 0..13 (its feature-map bit)");
      SpeciesPlacement rule;
      rule.bit = static_cast<int>(e->integer("bit", 0, 0, kFeatureTreeBits - 1));
      if (bits_used >> rule.bit & 1u) e->fail("bit", fmt::format("bit {} names two species", rule.bit));
      bits_used |= 1u << rule.bit;
      const Species& sp = load_species_once(e->file_path("species"));
      if (std::holds_alternative<FournierGrindalParams>(sp.model))
        e->fail("species", "a Fournier–Grindal species cannot be placed from a feature map (it has no trunk mesh)");
      species.push_back(&sp);
      materials.push_back(tree_materials(*e, sp, true));
      TreeOptions o;
      o.quality = e->real("quality", 1.0, 0.01, 100.0);
      if (options_.time_s) o.time_s = *options_.time_s;
      options.push_back(o);
      rule.density_per_ha = e->real("density", 100.0, 0.0, 1e6);
      rule.min_spacing_m = e->real("min_spacing", 2.0, 0.01, 1e4);
      if (rule.density_per_ha > 0 && std::sqrt(1e4 / rule.density_per_ha) <= rule.min_spacing_m)
        e->fail("density", fmt::format("a density of {:g} trees/ha cannot keep min_spacing = {:g} m (at most {:g})",
                                       rule.density_per_ha, rule.min_spacing_m, 1e4 / sqr(rule.min_spacing_m)));
      rule.scale_range = range(*e, "scale", Vec2(1.0f), 1e-3, 1e3);
      const int count = static_cast<int>(e->integer("variants", 1, 1, 1000));
      const uint64_t first_seed = static_cast<uint64_t>(e->integer("seed", 1, 0, INT64_MAX - 1000));
      for (int k = 0; k < count; ++k) variants.push_back({rules.size(), first_seed + static_cast<uint64_t>(k), {}, {}});
      rules.push_back(rule);
    }
    // Every variant once, in parallel; results (and the first error, in entry order) do not
    // depend on the thread count.
    tbb::parallel_for(size_t{0}, variants.size(), [&](size_t i) {
      Variant& v = variants[i];
      v.tree = generate_tree(*species[v.entry], v.seed, options[v.entry], true);
    });
    std::vector<std::vector<std::vector<uint32_t>>> protos(rules.size());
    std::vector<std::vector<size_t>> variant_index(rules.size());                // (entry, k-th variant) → variants
    std::vector<GeneratedTree> lod_sources(lod_.enabled ? variants.size() : 0);  // kept for the levels
    std::vector<std::vector<uint32_t>> variant_ids(rules.size());
    std::vector<uint32_t> class_ids;
    for (const Species* sp : species) class_ids.push_back(class_of(sp->name));
    for (Variant& v : variants) {
      const Params& e = *entries[v.entry];
      const std::filesystem::path file = e.file_path("species");
      if (!v.tree.error.empty()) e.fail("species", file.string() + ": " + v.tree.error);
      // The footprint: the widest bark vertex within 10 cm of the ground (flare and lobes included).
      float radius = 0.0f;
      for (const Vec3& p : v.tree.mesh.stems.positions)
        if (p.z < 0.1f) radius = std::max(radius, glm::length(Vec2(p)));
      rules[v.entry].trunk_radius_m.push_back(radius);
      const std::string name = fmt::format("{} seed {}", e.string("name", species[v.entry]->name), v.seed);
      const size_t index = static_cast<size_t>(&v - variants.data());
      if (lod_.enabled) {
        // Its prototypes (full and reduced) are added after placement, for the levels in use.
        v.bounds = bounds_of(v.tree.mesh);
        lod_sources[index] = std::move(v.tree);
        protos[v.entry].emplace_back();
      } else {
        protos[v.entry].push_back(add_tree_prototypes(e, name, v.tree, materials[v.entry]));
      }
      variant_index[v.entry].push_back(index);
      v.tree = GeneratedTree{};
      variant_ids[v.entry].push_back(
          variant_of(fmt::format("vegetation|{}|{}|{}", v.entry, file.string(), v.seed),
                     {"tree", species[v.entry]->name, file.string(), v.seed, class_ids[v.entry]}));
    }

    FeatureMap map;
    if (t->has("feature_map")) {
      for (const char* key : {"feature_resolution", "patch_size", "tree_cover", "grass_cover"})
        if (t->has(key))
          t->fail(key, fmt::format("'{}' is for a procedural feature map (one without 'feature_map')", key));
      const std::filesystem::path file = t->file_path("feature_map");
      try {
        map = read_feature_map(file, extent_min_, extent_max_);
      } catch (const ParseError&) {
        throw;
      } catch (const Error& e) {
        t->fail("feature_map", e.what());
      }
      uint32_t present = 0;
      for (const uint16_t v : map.bits) present |= v;
      for (int b = 0; b < kFeatureTreeBits; ++b)
        if ((present >> b & 1u) && !(bits_used >> b & 1u))
          t->fail("feature_map",
                  fmt::format("{}: bit {} is set but no [[vegetation.species]] has bit = {}", file.string(), b, b));
      for (const uint16_t v : map.bits)
        if (grass_type(v) > static_cast<int>(grass_.size()))
          t->fail("feature_map", fmt::format("{}: grass type {} is used but only {} [[grass]] type(s) are declared",
                                             file.string(), grass_type(v), grass_.size()));
    } else {
      ProceduralFeatureParams pf;
      pf.min_m = extent_min_;
      pf.max_m = extent_max_;
      pf.pixel_m = t->real("feature_resolution", pf.pixel_m, 0.01, 1e4);
      pf.patch_m = t->real("patch_size", pf.patch_m, 0.1, 1e6);
      pf.tree_cover = t->real("tree_cover", pf.tree_cover, 0.0, 1.0);
      pf.grass_cover = t->real("grass_cover", pf.grass_cover, 0.0, 1.0);
      for (const SpeciesPlacement& r : rules) pf.tree_bits.push_back(r.bit);
      pf.grass_types = static_cast<int>(grass_.size());
      pf.seed = seed;
      if (static_cast<double>((pf.max_m.x - pf.min_m.x) / pf.pixel_m) * ((pf.max_m.y - pf.min_m.y) / pf.pixel_m) >
          kMaxTerrainNodes)
        t->fail("feature_resolution", "the procedural feature map would be too large: raise feature_resolution");
      map = make_procedural_feature_map(pf);
    }

    std::vector<PlacedTree> trees;
    try {
      trees = place_trees(map, *terrain_, rules, seed);
    } catch (const Error& e) {
      t->fail(e.what());
    }
    uint32_t next_id = 1;
    for (const Instance& inst : out_.scene.instances) next_id = std::max(next_id, inst.object_id + 1);
    const int64_t first_id = t->integer("first_object_id", next_id, 1, 1 << 24);
    if (first_id + static_cast<int64_t>(trees.size()) > (int64_t{1} << 24))
      t->fail("first_object_id",
              fmt::format("{} trees from object id {} exceed the largest id, 2^24", trees.size(), first_id));
    const auto placed = [](const PlacedTree& tree) {
      Mat4 m = glm::translate(Mat4(1.0f), tree.base_m);
      m = glm::rotate(m, tree.heading_rad, Vec3(0, 0, 1));
      return glm::scale(m, Vec3(tree.scale));
    };
    // With [lod], each tree's level (docs/lod.md); a level's prototypes, the full tree's included,
    // are added only if some tree uses it, in variant then level order.
    const size_t levels = kLodLevelR2.size();
    std::vector<uint8_t> tree_level(lod_.enabled ? trees.size() : 0, 0);
    std::vector<uint8_t> used(variants.size() * levels, 0);
    for (size_t i = 0; i < tree_level.size(); ++i) {
      const size_t v = variant_index[trees[i].species][trees[i].variant];
      tree_level[i] = static_cast<uint8_t>(lod_level_of(variants[v].bounds, placed(trees[i])));
      used[v * levels + tree_level[i]] = 1;
    }
    std::vector<std::vector<uint32_t>> level_protos(variants.size() * levels);
    std::vector<LodJob> jobs = build_lod_levels(used, lod_sources);
    size_t job = 0;
    for (size_t v = 0; v < lod_sources.size(); ++v) {
      const Params& e = *entries[variants[v].entry];
      const std::string name =
          fmt::format("{} seed {}", e.string("name", species[variants[v].entry]->name), variants[v].seed);
      const std::vector<uint32_t>& mats = materials[variants[v].entry];
      if (used[v * levels]) level_protos[v * levels] = add_tree_prototypes(e, name, lod_sources[v], mats);
      for (; job < jobs.size() && jobs[job].variant == v; ++job)
        level_protos[v * levels + jobs[job].level] = add_lod_prototypes(e, name, jobs[job].lod, mats);
      lod_sources[v] = GeneratedTree{};
    }
    out_.scene.instances.reserve(out_.scene.instances.size() + trees.size());
    for (size_t i = 0; i < trees.size(); ++i) {
      const PlacedTree& tree = trees[i];
      const Mat4 m = placed(tree);
      const int level = tree_level.empty() ? 0 : tree_level[i];
      const size_t v = variant_index[tree.species][tree.variant];
      for (const uint32_t proto : lod_.enabled ? level_protos[v * levels + level] : protos[tree.species][tree.variant])
        out_.scene.instances.push_back(Instance{proto, m, static_cast<uint32_t>(first_id + static_cast<int64_t>(i)),
                                                class_ids[tree.species], variant_ids[tree.species][tree.variant]});
    }
    std::vector<float> patch_sizes;
    for (const GrassType& g : grass_) patch_sizes.push_back(g.patch_size_m);
    for (const PlacedPatch& patch : place_grass_patches(map, *terrain_, patch_sizes, seed)) {
      // Onto the local slope: z += slope · (x, y), blades stay vertical; then the heading.
      Mat4 shear(1.0f);
      shear[0][2] = patch.slope.x;
      shear[1][2] = patch.slope.y;
      const Mat4 m = glm::translate(Mat4(1.0f), patch.centre_m) * shear *
                     glm::rotate(Mat4(1.0f), patch.heading_rad, Vec3(0, 0, 1));
      out_.scene.instances.push_back(
          Instance{grass_[static_cast<size_t>(patch.grass_type - 1)].prototype, m, 0, kClassGrass, 0});
    }
  }

  void parse_output(const Params& root) {
    const Params* t = root.table("output");
    t->check_keys({"exr", "png", "exposure", "auto_exposure", "view"});
    OutputSection& o = out_.output;
    if (t->has("exr")) o.exr = t->string("exr");
    if (t->has("png")) o.png = t->string("png");
    o.exposure_ev = t->real("exposure", 0.0, -64.0, 64.0);
    o.auto_exposure = t->boolean("auto_exposure", true);
    o.view = t->string("view", o.view);
  }

  const Params& root_;
  std::filesystem::path base_dir_;
  SceneOptions options_;
  SceneFile out_;
  std::map<std::string, uint32_t> material_ids_;
  std::map<std::string, std::vector<uint32_t>> tree_prototypes_;
  std::map<std::string, Species> species_;
  std::map<std::string, uint32_t> variant_ids_;
  std::map<std::string, uint32_t> target_prototypes_;
  std::vector<std::pair<size_t, size_t>> automatic_ranges_;  // instance ranges with provisional object ids
  std::vector<PlacedMesh> ground_;                           // what [[targets]] snap onto (made on first use)
  bool ground_made_ = false;
  uint64_t dependency_hash_ = 0;
  // [terrain]: the height field and the extent a feature map covers; [[grass]]: the patch
  // prototype and size of each grass type.
  std::optional<HeightField> terrain_;
  bool camera_above_terrain_ = false;
  LodSettings lod_;  // [lod]
  Vec2 extent_min_{0.0f}, extent_max_{0.0f};
  struct GrassType {
    uint32_t prototype = 0;
    float patch_size_m = 0.0f;
  };
  std::vector<GrassType> grass_;
};

// Relative file names resolve against the scene's directory, then Sylva's data directory. Every
// file found is appended to `found` (in order, repeats included), so the scene hash can cover it.
FileResolver file_resolver(const std::filesystem::path& base_dir,
                           const std::shared_ptr<std::vector<std::filesystem::path>>& found) {
  return [base_dir, found](const std::string& rel) -> std::filesystem::path {
    const std::filesystem::path p(rel);
    std::filesystem::path out;
    if (p.is_absolute())
      out = std::filesystem::exists(p) ? p : std::filesystem::path();
    else if (!base_dir.empty() && std::filesystem::exists(base_dir / p))
      out = base_dir / p;
    else if (std::filesystem::exists(data_dir() / p))
      out = data_dir() / p;
    if (!out.empty()) found->push_back(out);
    return out;
  };
}

}  // namespace

SceneFile parse_scene(const std::string& text, const std::string& name, const std::filesystem::path& base_dir,
                      const SceneOptions& options) {
  TomlReader reader(name);
  toml::table document = reader.parse(text);
  apply_overrides(document, options.overrides);
  const auto found = std::make_shared<std::vector<std::filesystem::path>>();
  const Params root = reader.to_params(document, "the scene", file_resolver(base_dir, found));
  SceneParser parser(root, base_dir, options);
  SceneFile file = parser.parse();
  // The species files (and their templates) are chained first, as read; then every other file the
  // scene read (meshes, spectrum and SRF tables), each once, in the order first named. So editing
  // any input changes the hash, and a checkpoint or golden record of the old scene is refused.
  uint64_t dependencies = parser.dependency_hash();
  std::vector<std::filesystem::path> hashed;
  for (const std::filesystem::path& f : *found) {
    if (parser.is_species_file(f) || std::find(hashed.begin(), hashed.end(), f) != hashed.end()) continue;
    hashed.push_back(f);
    dependencies = hash_ids(dependencies, mix64(fnv1a64_of_file(f, kMaxMeshFileBytes, "scene input")));
    file.inputs.push_back(f);
  }
  for (const auto& [species_file, species] : parser.species()) {
    file.inputs.emplace_back(species_file);
    if (const auto* tm = std::get_if<TreeMakerTemplate>(&species.model); tm != nullptr && tm->source != species_file)
      file.inputs.push_back(tm->source);
  }
  uint64_t hash = hash_ids(hash_text(text), dependencies);
  if (options.time_s) hash = hash_ids(hash, hash_text(fmt::format("time {:a}", *options.time_s)));
  for (const std::string& o : options.overrides) hash = hash_ids(hash, hash_text("--set " + o));
  file.content_hash = hex64(hash);
  return file;
}

SceneFile load_scene_file(const std::filesystem::path& path, const SceneOptions& options) {
  const std::string text = read_input_file(path, kMaxSceneFileBytes, "scene file");
  SceneFile f = parse_scene(text, path.string(), path.parent_path().empty() ? "." : path.parent_path(), options);
  f.path = path;
  f.inputs.insert(f.inputs.begin(), path);
  return f;
}

SceneFile default_scene(const SceneOptions& options) {
  return parse_scene(kDefaultSceneText, "<default scene>", data_dir(), options);
}

std::vector<Band> resolve_bands(const SceneFile& file, const std::vector<std::string>& names) {
  std::vector<Band> bands;
  for (const std::string& n : names) {
    bool found = false;
    for (const Band& b : file.custom_bands)
      if (b.name == n) {
        bands.push_back(b);
        found = true;
      }
    if (!found) bands.push_back(resolve_band(n));
    for (size_t i = 0; i + 1 < bands.size(); ++i)
      if (bands[i].name == n) throw Error("band '" + n + "' is requested twice");
  }
  return bands;
}

RenderSettings render_settings(const SceneFile& file) {
  RenderSettings s = file.render;
  s.bands = resolve_bands(file, file.bands);
  return s;
}

void annotate_render(Image& image, const SceneFile& file, const RenderSettings& settings) {
  image.set_attribute("sylva:version", SYLVA_VERSION);
  image.set_attribute("sylva:spp", std::to_string(settings.spp));
  image.set_attribute("sylva:seed", std::to_string(settings.seed));
  image.set_attribute("sylva:scene", file.path.empty() ? "<default scene>" : file.path.filename().string());
  image.set_attribute("sylva:scene_hash", file.content_hash);
  image.set_attribute("sylva:max_depth", std::to_string(settings.integrator.max_depth));
  // The kernels that traced it: renders agree bit for bit only on the same set (EmbreeIsa).
  image.set_attribute("sylva:embree_isa", embree_isa_name(resolve_embree_isa(settings.isa)));
  std::string bands;
  for (const Band& b : settings.bands) bands += (bands.empty() ? "" : ",") + b.name;
  image.set_attribute("sylva:bands", bands);
  image.set_attribute("sylva:quantity", quantity_name(settings.quantity));
  // The band-weighted horizontal irradiance per channel: the divisor of the reflectance factor.
  const std::vector<float> e = channel_irradiance(Environment(file.scene.sun, file.scene.sky), settings.bands);
  std::string irradiance;
  size_t c = 0;
  for (const Band& b : settings.bands)
    for (const std::string& name : b.channels) {
      irradiance += fmt::format("{}{}={:.7g}", c ? "," : "", name, e[c]);
      ++c;
    }
  image.set_attribute("sylva:irradiance", irradiance);
  const std::string values =
      settings.quantity == Quantity::reflectance
          ? "band channels: reflectance factor pi L_c / E_c, E_c = band-weighted irradiance on a "
            "horizontal plane from the sun and sky (sylva:irradiance, W m^-2 nm^-1)"
          : "band channels: SRF-weighted mean spectral radiance, W m^-2 sr^-1 nm^-1";
  image.set_attribute("sylva:units",
                      values +
                          "; R,G,B: CIE 1931 XYZ (Y = luminance-weighted mean) in linear Rec.709 primaries; var.*: "
                          "variance of the pixel mean; Z: camera-space depth, m");
}

}  // namespace sylva

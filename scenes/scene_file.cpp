#include "scenes/scene_file.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/prospect.h"
#include "geometry/mesh_io.h"
#include "geometry/primitives.h"
#include "scenes/species.h"
#include "scenes/toml_reader.h"

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

#include <fstream>
#include <map>
#include <sstream>

namespace sylva {

namespace {

const char* const kDefaultSceneText =
#include "scenes/default_scene.inc"
    ;

uint64_t hash_text(std::string_view text) { return mix64(fnv1a64(text)); }

class SceneParser {
 public:
  SceneParser(TomlReader& reader, std::filesystem::path base_dir) : r_(reader), base_dir_(std::move(base_dir)) {}

  SceneFile parse(const toml::table& root) {
    r_.check_keys(root, {"camera", "sun", "sky", "materials", "meshes", "trees", "render", "output", "bands"},
                  "the scene");
    parse_render(root);
    parse_bands(root);
    parse_camera(root);
    parse_sun(root);
    parse_sky(root);
    parse_materials(root);
    parse_meshes(root);
    parse_trees(root);
    parse_output(root);
    return std::move(out_);
  }

  // Hash of everything the scene reads besides its own text (species files), for checkpoints and
  // golden headers.
  uint64_t dependency_hash() const { return dependency_hash_; }

 private:
  std::filesystem::path resolve(const toml::node& at, const std::string& rel) const {
    const std::filesystem::path p(rel);
    if (p.is_absolute()) {
      if (!std::filesystem::exists(p)) r_.fail(at, "file not found: " + rel);
      return p;
    }
    if (!base_dir_.empty() && std::filesystem::exists(base_dir_ / p)) return base_dir_ / p;
    if (std::filesystem::exists(data_dir() / p)) return data_dir() / p;
    r_.fail(at, "file not found: " + rel + " (looked in " +
                    (base_dir_.empty() ? std::string("") : base_dir_.string() + " and ") + data_dir().string() + ")");
  }

  // A spectrum: a number (constant), a builtin name, {file, column}, or {lambda_nm, value}.
  DenseSpectrum spectrum(const toml::node& node, Extrapolate outside) {
    if (node.is_number()) return DenseSpectrum::constant(static_cast<float>(*node.value<double>()));
    if (const auto* s = node.as_string()) {
      const std::string name = s->get();
      if (name == "astm-g173-direct") return astm_g173_direct();
      if (name == "astm-g173-diffuse") return astm_g173_diffuse();
      if (name == "astm-g173-global") return astm_g173_global();
      r_.fail(node, "unknown spectrum '" + name +
                        "' (expected a number, astm-g173-direct, astm-g173-diffuse, astm-g173-global, "
                        "{ file, column } or { lambda_nm, value })");
    }
    const toml::table* t = node.as_table();
    if (!t) r_.fail(node, "expected a spectrum: a number, a name, { file, column } or { lambda_nm, value }");
    if (t->contains("file")) {
      r_.check_keys(*t, {"file", "column", "scale"}, "a tabulated spectrum");
      const std::filesystem::path file = resolve(*t->get("file"), r_.string(*t, "file"));
      const std::string column = r_.string(*t, "column");
      DenseSpectrum s;
      try {
        s = load_spectrum(file, column, outside);
      } catch (const Error& e) {
        r_.fail(*t, e.what());
      }
      s *= static_cast<float>(r_.number(*t, "scale", 1.0));
      return s;
    }
    r_.check_keys(*t, {"lambda_nm", "value", "scale"}, "an inline spectrum");
    const std::vector<double> l = r_.numbers(*t, "lambda_nm");
    const std::vector<double> v = r_.numbers(*t, "value");
    if (l.size() != v.size() || l.empty()) r_.fail(*t, "lambda_nm and value must be non-empty arrays of equal length");
    for (size_t i = 1; i < l.size(); ++i)
      if (!(l[i] > l[i - 1])) r_.fail(*t->get("lambda_nm"), "lambda_nm must increase strictly");
    DenseSpectrum s = DenseSpectrum::from_samples(l, v, outside);
    s *= static_cast<float>(r_.number(*t, "scale", 1.0));
    return s;
  }

  void parse_render(const toml::table& root) {
    const toml::table* t = r_.table(root, "render");
    if (!t) return;
    r_.check_keys(*t, {"width", "height", "spp", "seed", "max_depth", "bands"}, "[render]");
    RenderSection& rs = out_.render;
    rs.width = r_.integer(*t, "width", rs.width, 1, 65536);
    rs.height = r_.integer(*t, "height", rs.height, 1, 65536);
    rs.spp = r_.integer(*t, "spp", rs.spp, 1, 1 << 24);
    rs.seed = static_cast<uint64_t>(r_.integer(*t, "seed", static_cast<int64_t>(rs.seed), 0, INT64_MAX));
    rs.max_depth = r_.integer(*t, "max_depth", rs.max_depth, 1, 1024);
    if (t->contains("bands")) rs.bands = r_.strings(*t, "bands");
  }

  void parse_bands(const toml::table& root) {
    const toml::array* a = r_.array(root, "bands");
    if (!a) return;
    for (const toml::node& n : *a) {
      const toml::table* t = n.as_table();
      if (!t) r_.fail(n, "expected a table: [[bands]] name = ..., response = { file, column } or { lambda_nm, value }");
      r_.check_keys(*t, {"name", "response"}, "[[bands]]");
      const std::string name = r_.string(*t, "name");
      if (name.empty() || name.find_first_of(" .,") != std::string::npos)
        r_.fail(*t->get("name"), "band name must be non-empty without spaces, dots or commas");
      const toml::node* resp = t->get("response");
      if (!resp) r_.fail(*t, "[[bands]] needs a response spectrum");
      try {
        out_.custom_bands.push_back(make_srf_band(name, spectrum(*resp, Extrapolate::Zero)));
      } catch (const ParseError&) {
        throw;
      } catch (const Error& e) {
        r_.fail(*resp, e.what());
      }
    }
  }

  void parse_camera(const toml::table& root) {
    const toml::table* t = r_.table(root, "camera");
    if (!t) return;
    r_.check_keys(*t, {"position", "target", "up", "vfov", "aperture_radius", "focus_distance"}, "[camera]");
    CameraDesc& c = out_.scene.camera;
    c.position = r_.vec3(*t, "position", c.position);
    c.target = r_.vec3(*t, "target", c.target);
    c.up = r_.vec3(*t, "up", c.up);
    c.vfov_deg = r_.number_in(*t, "vfov", c.vfov_deg, 0.01, 179.0);
    c.aperture_radius_m = r_.number_in(*t, "aperture_radius", c.aperture_radius_m, 0.0, 100.0);
    c.focus_distance_m = r_.number_in(*t, "focus_distance", c.focus_distance_m, 0.0, 1e6);
    if (glm::length(c.target - c.position) <= 0) r_.fail(*t, "camera position and target must differ");
    if (glm::length(glm::cross(glm::normalize(c.target - c.position), c.up)) < 1e-4f)
      r_.fail(*t, "camera up must not be parallel to the view direction");
  }

  void parse_sun(const toml::table& root) {
    const toml::table* t = r_.table(root, "sun");
    if (!t) return;
    r_.check_keys(*t, {"enabled", "azimuth", "elevation", "angular_radius", "irradiance", "scale"}, "[sun]");
    SunDesc& s = out_.scene.sun;
    s.enabled = r_.boolean(*t, "enabled", true);
    s.azimuth_deg = r_.number_in(*t, "azimuth", s.azimuth_deg, -360.0, 360.0);
    s.elevation_deg = r_.number_in(*t, "elevation", s.elevation_deg, -90.0, 90.0);
    s.angular_radius_deg = r_.number_in(*t, "angular_radius", s.angular_radius_deg, 1e-3, 10.0);
    if (const toml::node* n = t->get("irradiance")) s.irradiance = spectrum(*n, Extrapolate::Zero);
    s.irradiance *= static_cast<float>(r_.number_in(*t, "scale", 1.0, 0.0, 1e6));
  }

  void parse_sky(const toml::table& root) {
    const toml::table* t = r_.table(root, "sky");
    if (!t) return;
    r_.check_keys(*t, {"model", "type", "spectrum", "scale", "ground_albedo"}, "[sky]");
    SkyDesc& s = out_.scene.sky;
    const std::string model = r_.string(*t, "model", "cie");
    if (model == "cie") {
      s.model = SkyModel::CieStandard;
      s.cie_type = r_.integer(*t, "type", s.cie_type, 1, 15);
    } else if (model == "uniform") {
      s.model = SkyModel::Uniform;
      s.spectrum = DenseSpectrum::constant(1.0f);
    } else if (model == "none") {
      s.enabled = false;
    } else {
      r_.fail(*t->get("model"), "sky model must be \"cie\", \"uniform\" or \"none\"");
    }
    if (const toml::node* n = t->get("spectrum")) s.spectrum = spectrum(*n, Extrapolate::Zero);
    s.spectrum *= static_cast<float>(r_.number_in(*t, "scale", 1.0, 0.0, 1e6));
    s.ground_albedo = r_.number_in(*t, "ground_albedo", 0.0, 0.0, 1.0);
    if (s.ground_albedo > 0 && !(s.enabled && s.model == SkyModel::CieStandard))
      r_.fail(*t->get("ground_albedo"), "ground_albedo needs model = \"cie\"");
  }

  void parse_materials(const toml::table& root) {
    const toml::table* t = r_.table(root, "materials");
    if (!t) return;
    for (const auto& [key, node] : *t) {
      const std::string name(key.str());
      const toml::table* m = node.as_table();
      if (!m) r_.fail(node, "material '" + name + "' must be a table");
      const std::string type = r_.string(*m, "type", "diffuse");
      try {
        if (type == "diffuse") {
          r_.check_keys(*m, {"type", "reflectance"}, "a diffuse material");
          const toml::node* refl = m->get("reflectance");
          if (!refl) r_.fail(*m, "diffuse material '" + name + "' needs a reflectance");
          add_material(name, make_diffuse(name, spectrum(*refl, Extrapolate::Clamp)), *m);
        } else if (type == "leaf") {
          r_.check_keys(*m,
                        {"type", "reflectance", "transmittance", "back_reflectance", "back_transmittance", "prospect"},
                        "a leaf material");
          add_material(name, leaf_material(name, *m), *m);
        } else {
          r_.fail(*m, "material type must be \"diffuse\" or \"leaf\", not \"" + type + "\"");
        }
      } catch (const ParseError&) {
        throw;
      } catch (const Error& e) {
        r_.fail(*m, e.what());
      }
    }
  }

  Material leaf_material(const std::string& name, const toml::table& m) {
    if (const toml::table* p = r_.table(m, "prospect")) {
      r_.check_keys(*p, {"N", "Cab", "Car", "Ant", "Cbrown", "Cw", "Cm"}, "PROSPECT-D parameters");
      ProspectParams pp;
      pp.N = r_.number_in(*p, "N", pp.N, 1.0, 4.0);
      pp.Cab = r_.number_in(*p, "Cab", pp.Cab, 0.0, 200.0);
      pp.Car = r_.number_in(*p, "Car", pp.Car, 0.0, 50.0);
      pp.Ant = r_.number_in(*p, "Ant", pp.Ant, 0.0, 50.0);
      pp.Cbrown = r_.number_in(*p, "Cbrown", pp.Cbrown, 0.0, 5.0);
      pp.Cw = r_.number_in(*p, "Cw", pp.Cw, 0.0, 0.2);
      pp.Cm = r_.number_in(*p, "Cm", pp.Cm, 0.0, 0.1);
      if (m.contains("reflectance") || m.contains("transmittance"))
        r_.fail(m, "give either prospect = {...} or reflectance/transmittance, not both");
      const LeafOptics o = prospect_d(pp);
      const std::vector<double> l(o.lambda_nm.begin(), o.lambda_nm.end());
      const DenseSpectrum rho =
          DenseSpectrum::from_samples(l, {o.reflectance.begin(), o.reflectance.end()}, Extrapolate::Clamp);
      const DenseSpectrum tau =
          DenseSpectrum::from_samples(l, {o.transmittance.begin(), o.transmittance.end()}, Extrapolate::Clamp);
      return make_leaf(name, rho, tau);
    }
    const toml::node* rn = m.get("reflectance");
    const toml::node* tn = m.get("transmittance");
    if (!rn || !tn)
      r_.fail(m, "leaf material '" + name + "' needs reflectance and transmittance (or prospect = {...})");
    const DenseSpectrum rf = spectrum(*rn, Extrapolate::Clamp), tf = spectrum(*tn, Extrapolate::Clamp);
    const toml::node* rb = m.get("back_reflectance");
    const toml::node* tb = m.get("back_transmittance");
    return make_leaf(name, rf, tf, rb ? spectrum(*rb, Extrapolate::Clamp) : rf,
                     tb ? spectrum(*tb, Extrapolate::Clamp) : tf);
  }

  void add_material(const std::string& name, Material m, const toml::node& at) {
    if (material_ids_.count(name)) r_.fail(at, "material '" + name + "' is defined twice");
    material_ids_[name] = out_.scene.add_material(name, std::move(m));
  }

  uint32_t material_ref(const toml::table& t, const char* key) {
    const std::string name = r_.string(t, key);
    auto it = material_ids_.find(name);
    if (it == material_ids_.end()) {
      std::string known;
      for (const auto& [k, v] : material_ids_) known += (known.empty() ? "" : ", ") + k;
      r_.fail(*t.get(key), "unknown material '" + name + "' (defined: " + (known.empty() ? "none" : known) + ")");
    }
    return it->second;
  }

  // translate = [x,y,z], rotate = [rx,ry,rz] degrees (applied X, then Y, then Z), scale = s or [sx,sy,sz].
  Mat4 transform(const toml::table& t) {
    const Vec3 translate = r_.vec3(t, "translate", Vec3(0.0f));
    const Vec3 rotate = r_.vec3(t, "rotate", Vec3(0.0f));
    Vec3 scale(1.0f);
    if (const toml::node* s = t.get("scale")) {
      if (s->is_number())
        scale = Vec3(static_cast<float>(*s->value<double>()));
      else
        scale = r_.vec3(t, "scale", scale);
      if (scale.x <= 0 || scale.y <= 0 || scale.z <= 0) r_.fail(*s, "scale must be positive");
    }
    Mat4 m = glm::translate(Mat4(1.0f), translate);
    m = glm::rotate(m, radians(rotate.z), Vec3(0, 0, 1));
    m = glm::rotate(m, radians(rotate.y), Vec3(0, 1, 0));
    m = glm::rotate(m, radians(rotate.x), Vec3(1, 0, 0));
    return glm::scale(m, scale);
  }

  void parse_meshes(const toml::table& root) {
    const toml::array* a = r_.array(root, "meshes");
    if (!a) return;
    for (const toml::node& n : *a) {
      const toml::table* t = n.as_table();
      if (!t) r_.fail(n, "expected a table in [[meshes]]");
      r_.check_keys(*t, {"name",     "shape",     "file",   "material",    "size",       "radius",     "height",
                         "segments", "tiles",     "count",  "leaf_length", "leaf_width", "leaf_shape", "seed",
                         "radii",    "translate", "rotate", "scale",       "object_id",  "instances"},
                    "[[meshes]]");
      Prototype p;
      p.name = r_.string(*t, "name", fmt::format("mesh{}", out_.scene.prototypes.size()));
      const uint32_t material = material_ref(*t, "material");
      if (t->contains("file")) {
        if (t->contains("shape")) r_.fail(*t, "give either shape or file, not both");
        const std::filesystem::path file = resolve(*t->get("file"), r_.string(*t, "file"));
        p.triangles = read_mesh(file);
        p.triangle_material = material;
      } else {
        const std::string shape = r_.string(*t, "shape");
        if (shape == "plane") {
          const Vec2 size = r_.vec2(*t, "size", Vec2(10.0f));
          p.triangles = make_plane(size.x, size.y, r_.integer(*t, "tiles", 1, 1, 4096));
        } else if (shape == "box") {
          p.triangles = make_box(r_.vec3(*t, "size", Vec3(1.0f)));
        } else if (shape == "sphere") {
          p.triangles =
              make_sphere(r_.number_in(*t, "radius", 1.0, 1e-6, 1e6), r_.integer(*t, "segments", 24, 3, 4096));
        } else if (shape == "cylinder") {
          p.triangles =
              make_cylinder(r_.number_in(*t, "radius", 0.1, 1e-6, 1e6), r_.number_in(*t, "height", 1.0, 1e-6, 1e6),
                            r_.integer(*t, "segments", 24, 3, 4096));
        } else if (shape == "leaf_cloud") {
          LeafCloudParams lc;
          lc.radii = r_.vec3(*t, "radii", lc.radii);
          lc.count = r_.integer(*t, "count", lc.count, 1, 50'000'000);
          lc.leaf_length_m = r_.number_in(*t, "leaf_length", lc.leaf_length_m, 1e-4, 10.0);
          lc.leaf_width_m = r_.number_in(*t, "leaf_width", lc.leaf_width_m, 1e-4, 10.0);
          const std::string ls = r_.string(*t, "leaf_shape", "oval");
          const auto shape_id = leaf_shape_from_name(ls);
          if (!shape_id) r_.fail(*t->get("leaf_shape"), "unknown leaf_shape '" + ls + "'");
          lc.shape = *shape_id;
          p.leaves = make_leaf_cloud(lc, static_cast<uint64_t>(r_.integer(*t, "seed", 1, 0, INT64_MAX)));
        } else {
          r_.fail(t->get("shape") ? *t->get("shape") : static_cast<const toml::node&>(*t),
                  "shape must be plane, box, sphere, cylinder or leaf_cloud (or give file = \"mesh.obj|ply\")");
        }
        (p.leaves.size() > 0 ? p.leaf_material : p.triangle_material) = material;
      }
      place(*t, out_.scene.add_prototype(std::move(p)));
    }
  }

  // Places instances of a prototype: `instances = [{translate, rotate, scale, object_id}, ...]` or
  // the table's own transform.
  void place(const toml::table& t, uint32_t proto) {
    const uint32_t object_id = static_cast<uint32_t>(r_.integer(t, "object_id", 0, 0, 1 << 24));
    const Mat4 base = transform(t);
    if (const toml::array* inst = r_.array(t, "instances")) {
      for (const toml::node& in : *inst) {
        const toml::table* it = in.as_table();
        if (!it) r_.fail(in, "expected a table { translate, rotate, scale, object_id } in instances");
        r_.check_keys(*it, {"translate", "rotate", "scale", "object_id"}, "an instance");
        out_.scene.instances.push_back(Instance{
            proto, transform(*it) * base, static_cast<uint32_t>(r_.integer(*it, "object_id", object_id, 0, 1 << 24))});
      }
    } else {
      out_.scene.instances.push_back(Instance{proto, base, object_id});
    }
  }

  // [[trees]]: a generated tree (species file + seed), meshed once per distinct (species, seed,
  // options) and instanced.
  void parse_trees(const toml::table& root) {
    const toml::array* a = r_.array(root, "trees");
    if (!a) return;
    for (const toml::node& n : *a) {
      const toml::table* t = n.as_table();
      if (!t) r_.fail(n, "expected a table in [[trees]]");
      r_.check_keys(*t,
                    {"name", "species", "seed", "bark", "leaf", "quality", "time", "wind", "translate", "rotate",
                     "scale", "object_id", "instances"},
                    "[[trees]]");
      const std::string species_name = r_.string(*t, "species");
      const std::filesystem::path file = resolve(*t->get("species"), species_name);
      TreeOptions options;
      options.quality = r_.number_in(*t, "quality", 1.0, 0.01, 100.0);
      options.time_s = r_.number_in(*t, "time", 0.0, -1e9, 1e9);
      const Vec2 wind = r_.vec2(*t, "wind", Vec2(0.0f));
      if (wind.x < 0 || wind.y < 0) r_.fail(*t->get("wind"), "wind = [speed, gust] must not be negative");
      options.wind_speed = wind.x;
      options.wind_gust = wind.y;
      const uint64_t seed = static_cast<uint64_t>(r_.integer(*t, "seed", 1, 0, INT64_MAX));
      const uint32_t bark = material_ref(*t, "bark"), leaf = material_ref(*t, "leaf");
      const std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}|{}", file.string(), seed, options.quality,
                                          options.time_s, options.wind_speed, options.wind_gust, bark, leaf);
      auto it = tree_prototypes_.find(key);
      if (it == tree_prototypes_.end()) {
        auto sp = species_.find(file.string());
        if (sp == species_.end()) {
          std::ifstream in(file, std::ios::binary);
          std::stringstream text;
          text << in.rdbuf();
          dependency_hash_ = hash_ids(dependency_hash_, hash_text(text.str()));
          sp = species_.emplace(file.string(), parse_species(text.str(), file)).first;
          out_.warnings.insert(out_.warnings.end(), sp->second.warnings.begin(), sp->second.warnings.end());
        }
        TreeMesh mesh;
        try {
          mesh = make_species_mesh(sp->second, seed, options);
        } catch (const Error& e) {
          r_.fail(*t, file.string() + ": " + e.what());
        }
        Prototype p;
        p.name = r_.string(*t, "name", sp->second.name);
        p.triangles = std::move(mesh.stems);
        p.triangle_material = bark;
        p.leaves = std::move(mesh.leaves);
        p.leaf_material = leaf;
        it = tree_prototypes_.emplace(key, out_.scene.add_prototype(std::move(p))).first;
      }
      place(*t, it->second);
    }
  }

  void parse_output(const toml::table& root) {
    const toml::table* t = r_.table(root, "output");
    if (!t) return;
    r_.check_keys(*t, {"exr", "png", "exposure", "auto_exposure", "view"}, "[output]");
    OutputSection& o = out_.output;
    if (t->contains("exr")) o.exr = r_.string(*t, "exr");
    if (t->contains("png")) o.png = r_.string(*t, "png");
    o.exposure_ev = r_.number_in(*t, "exposure", 0.0, -64.0, 64.0);
    o.auto_exposure = r_.boolean(*t, "auto_exposure", true);
    o.view = r_.string(*t, "view", o.view);
  }

  TomlReader& r_;
  std::filesystem::path base_dir_;
  SceneFile out_;
  std::map<std::string, uint32_t> material_ids_;
  std::map<std::string, uint32_t> tree_prototypes_;
  std::map<std::string, Species> species_;
  uint64_t dependency_hash_ = 0;
};

}  // namespace

SceneFile parse_scene(const std::string& text, const std::string& name, const std::filesystem::path& base_dir) {
  TomlReader reader(name);
  const toml::table root = reader.parse(text);
  SceneParser parser(reader, base_dir);
  SceneFile file = parser.parse(root);
  file.content_hash = hex64(hash_ids(hash_text(text), parser.dependency_hash()));
  return file;
}

SceneFile load_scene_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path, 0, "cannot open scene file");
  std::stringstream ss;
  ss << in.rdbuf();
  SceneFile f = parse_scene(ss.str(), path.string(), path.parent_path().empty() ? "." : path.parent_path());
  f.path = path;
  return f;
}

SceneFile default_scene() { return parse_scene(kDefaultSceneText, "<default scene>", data_dir()); }

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
  RenderSettings s;
  s.width = file.render.width;
  s.height = file.render.height;
  s.spp = file.render.spp;
  s.seed = file.render.seed;
  s.integrator.max_depth = file.render.max_depth;
  s.bands = resolve_bands(file, file.render.bands);
  return s;
}

void annotate_render(Image& image, const SceneFile& file, const RenderSettings& settings) {
  image.set_attribute("sylva:version", SYLVA_VERSION);
  image.set_attribute("sylva:spp", std::to_string(settings.spp));
  image.set_attribute("sylva:seed", std::to_string(settings.seed));
  image.set_attribute("sylva:scene", file.path.empty() ? "<default scene>" : file.path.filename().string());
  image.set_attribute("sylva:scene_hash", file.content_hash);
  image.set_attribute("sylva:max_depth", std::to_string(settings.integrator.max_depth));
  std::string bands;
  for (const Band& b : settings.bands) bands += (bands.empty() ? "" : ",") + b.name;
  image.set_attribute("sylva:bands", bands);
  image.set_attribute("sylva:units",
                      "band channels: SRF-weighted mean spectral radiance, W m^-2 sr^-1 nm^-1; R,G,B: CIE 1931 XYZ "
                      "(Y = luminance-weighted mean spectral radiance) in linear Rec.709 primaries; var.*: variance "
                      "of the pixel mean; Z: camera-space depth, m");
}

}  // namespace sylva

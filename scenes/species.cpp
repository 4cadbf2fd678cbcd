#include "scenes/species.h"

#include "core/error.h"
#include "geometry/trees/tree_mesher.h"
#include "scenes/toml_reader.h"

#include <fmt/core.h>
#include <toml++/toml.h>
#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace sylva {

namespace {

// One parameter value as read from a file: a number, or a string (LeafShape, Species).
struct Value {
  bool is_number = false;
  double number = 0.0;
  std::string text;
};

struct Spec {
  std::string_view name;
  bool integer;
  double lo, hi;
  std::function<void(WeberPennParams&, double)> set;
};

struct LevelSpec {
  std::string_view name;
  bool integer;
  double lo, hi;
  std::function<void(WeberPennLevel&, double)> set;
};

constexpr double kInf = 1e30;

const std::vector<Spec>& global_specs() {
  using P = WeberPennParams;
  static const std::vector<Spec> specs = {
      {"Shape", true, 0, 8, [](P& p, double v) { p.shape = static_cast<int>(v); }},
      {"BaseSize", false, 0, 1, [](P& p, double v) { p.base_size = static_cast<float>(v); }},
      {"Scale", false, 1e-6, kInf, [](P& p, double v) { p.scale = static_cast<float>(v); }},
      {"ScaleV", false, 0, kInf, [](P& p, double v) { p.scale_v = static_cast<float>(v); }},
      {"ZScale", false, 1e-6, kInf, [](P& p, double v) { p.z_scale = static_cast<float>(v); }},
      {"ZScaleV", false, 0, kInf, [](P& p, double v) { p.z_scale_v = static_cast<float>(v); }},
      {"Levels", true, 1, 9, [](P& p, double v) { p.levels = static_cast<int>(v); }},
      {"Ratio", false, 1e-6, kInf, [](P& p, double v) { p.ratio = static_cast<float>(v); }},
      {"RatioPower", false, -kInf, kInf, [](P& p, double v) { p.ratio_power = static_cast<float>(v); }},
      {"Lobes", true, 0, 255, [](P& p, double v) { p.lobes = static_cast<int>(v); }},
      {"LobeDepth", false, 0, kInf, [](P& p, double v) { p.lobe_depth = static_cast<float>(v); }},
      {"Flare", false, -1, kInf, [](P& p, double v) { p.flare = static_cast<float>(v); }},
      {"0Scale", false, 1e-6, kInf, [](P& p, double v) { p.trunk_scale = static_cast<float>(v); }},
      {"0ScaleV", false, 0, kInf, [](P& p, double v) { p.trunk_scale_v = static_cast<float>(v); }},
      {"0BaseSplits", true, 0, 64, [](P& p, double v) { p.base_splits = static_cast<int>(v); }},
      {"Leaves", true, -100000, 100000, [](P& p, double v) { p.leaves = static_cast<int>(v); }},
      {"LeafScale", false, 1e-6, kInf, [](P& p, double v) { p.leaf_scale = static_cast<float>(v); }},
      {"LeafScaleX", false, 1e-6, kInf, [](P& p, double v) { p.leaf_scale_x = static_cast<float>(v); }},
      {"AttractionUp", false, -kInf, kInf, [](P& p, double v) { p.attraction_up = static_cast<float>(v); }},
      {"PruneRatio", false, 0, 1, [](P& p, double v) { p.prune_ratio = static_cast<float>(v); }},
      {"PruneWidth", false, 0, kInf, [](P& p, double v) { p.envelope.width = static_cast<float>(v); }},
      {"PruneWidthPeak", false, 0, 1, [](P& p, double v) { p.envelope.width_peak = static_cast<float>(v); }},
      {"PrunePowerLow", false, 0, kInf, [](P& p, double v) { p.envelope.power_low = static_cast<float>(v); }},
      {"PrunePowerHigh", false, 0, kInf, [](P& p, double v) { p.envelope.power_high = static_cast<float>(v); }},
      {"LeafBend", false, 0, 1, [](P& p, double v) { p.leaf_bend = static_cast<float>(v); }},
      {"LeafStemLen", false, -kInf, kInf, [](P& p, double v) { p.leaf_stem_len = static_cast<float>(v); }},
      {"LeafDistrib", true, 0, 8, [](P& p, double v) { p.leaf_distrib = static_cast<int>(v); }},
      {"LeafQuality", false, 1e-6, 1, [](P& p, double v) { p.leaf_quality = static_cast<float>(v); }},
  };
  return specs;
}

const std::vector<LevelSpec>& level_specs() {
  using L = WeberPennLevel;
  static const std::vector<LevelSpec> specs = {
      {"Length", false, 0, kInf, [](L& l, double v) { l.length = static_cast<float>(v); }},
      {"LengthV", false, 0, kInf, [](L& l, double v) { l.length_v = static_cast<float>(v); }},
      // Arbaro caps nTaper just below 3; the formula of §4.4 is defined on [0, 3).
      {"Taper", false, 0, 3, [](L& l, double v) { l.taper = static_cast<float>(std::min(v, 2.99999)); }},
      {"SegSplits", false, 0, kInf, [](L& l, double v) { l.seg_splits = static_cast<float>(v); }},
      {"SplitAngle", false, 0, 180, [](L& l, double v) { l.split_angle = static_cast<float>(v); }},
      {"SplitAngleV", false, 0, 180, [](L& l, double v) { l.split_angle_v = static_cast<float>(v); }},
      {"CurveRes", true, 1, 10000, [](L& l, double v) { l.curve_res = static_cast<int>(v); }},
      {"Curve", false, -kInf, kInf, [](L& l, double v) { l.curve = static_cast<float>(v); }},
      {"CurveBack", false, -kInf, kInf, [](L& l, double v) { l.curve_back = static_cast<float>(v); }},
      {"CurveV", false, -90, kInf, [](L& l, double v) { l.curve_v = static_cast<float>(v); }},
      {"DownAngle", false, -180, 180, [](L& l, double v) { l.down_angle = static_cast<float>(v); }},
      {"DownAngleV", false, -180, 180, [](L& l, double v) { l.down_angle_v = static_cast<float>(v); }},
      {"Rotate", false, -360, 360, [](L& l, double v) { l.rotate = static_cast<float>(v); }},
      {"RotateV", false, -360, 360, [](L& l, double v) { l.rotate_v = static_cast<float>(v); }},
      {"Branches", true, -100000, 100000, [](L& l, double v) { l.branches = static_cast<int>(v); }},
      {"BranchDist", false, 0, 1, [](L& l, double v) { l.branch_dist = static_cast<float>(v); }},
  };
  return specs;
}

std::string format_number(double v) { return fmt::format("{}", v); }

// Collects parameters from either format, with duplicate detection and file:line errors.
class ParamSink {
 public:
  ParamSink(std::filesystem::path file, WeberPennParams& params, std::vector<std::string>& warnings)
      : file_(std::move(file)), p_(params), warnings_(warnings) {}

  [[noreturn]] void fail(int line, const std::string& what) const { throw ParseError(file_, line, what); }
  void warn(int line, const std::string& what) const {
    warnings_.push_back(fmt::format("{}:{}: warning: {}", file_.string(), line, what));
  }

  // Sets parameter `name` (the paper's spelling, level prefix included) from `value`.
  void set(const std::string& name, const Value& value, int line) {
    if (const auto it = seen_.find(name); it != seen_.end())
      fail(line, fmt::format("parameter '{}' given twice (first on line {})", name, it->second));
    seen_.emplace(name, line);

    if (name == "LeafShape") return set_leaf_shape(value, line);
    if (name == "Smooth") {
      number(name, value, line, false, 0, 1);
      warn(line, "'Smooth' (Arbaro's mesh smoothing) is ignored; Sylva's mesh resolution follows --quality");
      return;
    }
    for (const Spec& s : global_specs()) {
      if (s.name != name) continue;
      s.set(p_, number(name, value, line, s.integer, s.lo, s.hi));
      return;
    }
    if (name.size() > 1 && name[0] >= '0' && name[0] <= '9') {
      const int level = name[0] - '0';
      const std::string_view key = std::string_view(name).substr(1);
      for (const LevelSpec& s : level_specs()) {
        if (s.name != key) continue;
        if (level > 3) fail(line, fmt::format("'{}': levels deeper than 3 reuse level 3's parameters", name));
        s.set(p_.level[static_cast<size_t>(level)], number(name, value, line, s.integer, s.lo, s.hi));
        return;
      }
    }
    fail(line, fmt::format("unknown parameter '{}'", name));
  }

 private:
  double number(const std::string& name, const Value& v, int line, bool integer, double lo, double hi) const {
    if (!v.is_number) fail(line, fmt::format("'{}' must be a number, not \"{}\"", name, v.text));
    if (!std::isfinite(v.number)) fail(line, fmt::format("'{}' must be finite", name));
    if (integer && v.number != std::floor(v.number))
      fail(line, fmt::format("'{}' must be an integer, not {}", name, format_number(v.number)));
    if (v.number < lo || v.number > hi) {
      if (hi >= kInf)
        fail(line, fmt::format("'{}' must be at least {}, not {}", name, format_number(lo), format_number(v.number)));
      if (lo <= -kInf)
        fail(line, fmt::format("'{}' must be at most {}, not {}", name, format_number(hi), format_number(v.number)));
      fail(line, fmt::format("'{}' must be in [{}, {}], not {}", name, format_number(lo), format_number(hi),
                             format_number(v.number)));
    }
    return v.number;
  }

  // The paper's ids 0..5 (oval, triangle, oak3, maple3, maple5, leaflets3) or those names;
  // Arbaro's "disc"/"discN" mean oval, its "sphere" and "palm" are not flat outlines (warned).
  void set_leaf_shape(const Value& v, int line) {
    if (v.is_number) {
      if (v.number != std::floor(v.number) || v.number < 0 || v.number > 5)
        fail(line,
             fmt::format("'LeafShape' must be an id 0..5 (oval, triangle, oak3, maple3, maple5, leaflets3), not {}",
                         format_number(v.number)));
      p_.leaf_shape = static_cast<LeafShape>(static_cast<int>(v.number) + static_cast<int>(LeafShape::Oval));
      return;
    }
    if (v.text.rfind("disc", 0) == 0) {
      p_.leaf_shape = LeafShape::Oval;
      return;
    }
    if (v.text == "sphere" || v.text == "palm") {
      p_.leaf_shape = LeafShape::Oval;
      warn(line, fmt::format("Arbaro leaf shape \"{}\" is drawn as an oval leaf", v.text));
      return;
    }
    const std::optional<LeafShape> shape = leaf_shape_from_name(v.text);
    if (!shape || *shape == LeafShape::Rectangle)
      fail(line,
           fmt::format("unknown LeafShape \"{}\" (expected 0..5 or oval, triangle, oak3, maple3, maple5, leaflets3)",
                       v.text));
    p_.leaf_shape = *shape;
  }

  std::filesystem::path file_;
  WeberPennParams& p_;
  std::vector<std::string>& warnings_;
  std::map<std::string, int> seen_;
};

bool parse_double(std::string_view s, double& out) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

Species parse_toml(const std::string& text, const std::filesystem::path& file) {
  TomlReader reader(file.string());
  const toml::table root = reader.parse(text);
  Species species;
  species.file = file;
  species.name = file.stem().string();
  WeberPennParams params;
  ParamSink sink(file, params, species.warnings);

  const toml::node* model = root.get("model");
  if (!model) reader.fail_line(1, "missing key 'model' (e.g. model = \"weber-penn\")");
  if (!model->is_string()) reader.fail(*model, "'model' must be a string");
  const std::string model_name = model->as_string()->get();
  if (model_name != "weber-penn")
    reader.fail(*model, fmt::format("unknown model \"{}\" (this version reads \"weber-penn\")", model_name));

  auto to_value = [&](const toml::node& n, const std::string& name) {
    Value v;
    if (const auto* i = n.as_integer()) {
      v.is_number = true;
      v.number = static_cast<double>(i->get());
    } else if (const auto* f = n.as_floating_point()) {
      v.is_number = true;
      v.number = f->get();
    } else if (const auto* s = n.as_string()) {
      v.text = s->get();
    } else {
      reader.fail(n, fmt::format("'{}' must be a number", name));
    }
    return v;
  };
  auto line_of = [](const toml::node& n) { return static_cast<int>(n.source().begin.line); };

  for (const auto& [key, node] : root) {
    const std::string name(key.str());
    if (name == "model") continue;
    if (name == "name") {
      if (!node.is_string()) reader.fail(node, "'name' must be a string");
      species.name = node.as_string()->get();
      continue;
    }
    if (node.is_table()) {
      if (name.size() != 6 || name.rfind("level", 0) != 0 || name[5] < '0' || name[5] > '3')
        reader.fail(node, fmt::format("unknown table [{}] (expected [level0] .. [level3])", name));
      for (const auto& [lkey, lnode] : *node.as_table()) {
        const std::string lname(lkey.str());
        if (lnode.is_table() || lnode.is_array()) reader.fail(lnode, fmt::format("'{}' must be a number", lname));
        bool known = false;
        for (const LevelSpec& s : level_specs()) known = known || s.name == lname;
        if (!known) reader.fail(lnode, fmt::format("unknown level parameter '{}' in [{}]", lname, name));
        sink.set(std::string(1, name[5]) + lname, to_value(lnode, lname), line_of(lnode));
      }
      continue;
    }
    if (node.is_array()) reader.fail(node, fmt::format("'{}' must be a number", name));
    sink.set(name, to_value(node, name), line_of(node));
  }
  species.model = params;
  return species;
}

int line_at(const std::string& text, ptrdiff_t offset) {
  if (offset < 0) return 0;
  const auto end = text.begin() + std::min<ptrdiff_t>(offset, static_cast<ptrdiff_t>(text.size()));
  return 1 + static_cast<int>(std::count(text.begin(), end, '\n'));
}

Species parse_arbaro_xml(const std::string& text, const std::filesystem::path& file) {
  pugi::xml_document doc;
  const pugi::xml_parse_result result = doc.load_buffer(text.data(), text.size());
  if (!result) throw ParseError(file, line_at(text, result.offset), fmt::format("XML: {}", result.description()));
  const pugi::xml_node root = doc.child("arbaro");
  if (!root) throw ParseError(file, 1, "not an Arbaro species file: expected an <arbaro> root element");
  const pugi::xml_node sp = root.child("species");
  if (!sp) throw ParseError(file, line_at(text, root.offset_debug()), "<arbaro> has no <species> element");

  Species species;
  species.file = file;
  species.name = sp.attribute("name") ? sp.attribute("name").value() : file.stem().string();
  WeberPennParams params;
  ParamSink sink(file, params, species.warnings);
  for (const pugi::xml_node node : sp.children()) {
    if (node.type() != pugi::node_element) continue;
    const int line = line_at(text, node.offset_debug());
    if (std::string_view(node.name()) != "param")
      throw ParseError(file, line,
                       fmt::format("unexpected <{}> in <species> (expected <param name=... value=.../>)", node.name()));
    const pugi::xml_attribute name = node.attribute("name");
    const pugi::xml_attribute value = node.attribute("value");
    if (!name) throw ParseError(file, line, "<param> without a name attribute");
    if (!value)
      throw ParseError(file, line, fmt::format("<param name=\"{}\"> without a value attribute", name.value()));
    const std::string pname = name.value();
    if (pname == "Species") {
      species.name = value.value();
      continue;
    }
    Value v;
    v.text = value.value();
    v.is_number = parse_double(v.text, v.number);
    sink.set(pname, v, line);
  }
  species.model = params;
  return species;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

Species parse_species(const std::string& text, const std::filesystem::path& file) {
  const std::string ext = lower(file.extension().string());
  if (ext == ".toml") return parse_toml(text, file);
  if (ext == ".xml") return parse_arbaro_xml(text, file);
  throw ParseError(file, 0, "unknown species file type (expected .toml or .xml)");
}

Species load_species(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ParseError(file, 0, "cannot open species file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_species(ss.str(), file);
}

TreeModel make_species_model(const Species& species, uint64_t seed, const TreeOptions& options) {
  return std::visit(
      [&](const WeberPennParams& base) {
        WeberPennParams p = base;
        p.quality = options.quality;
        p.wind.speed = options.wind_speed;
        p.wind.gust = options.wind_gust;
        p.wind.time_s = options.time_s;
        return make_weber_penn_tree(p, seed);
      },
      species.model);
}

TreeMesh make_species_mesh(const Species& species, uint64_t seed, const TreeOptions& options) {
  TreeMeshOptions mesh_options;
  mesh_options.quality = options.quality;
  return make_tree_mesh(make_species_model(species, seed, options), mesh_options);
}

}  // namespace sylva

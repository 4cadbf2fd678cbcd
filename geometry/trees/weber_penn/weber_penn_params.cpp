#include "geometry/trees/weber_penn/weber_penn.h"

#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

namespace sylva {

namespace {

using Value = ParamValue;

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

// Sets Weber-Penn parameters by the paper's names, with duplicate detection and file:line errors.
class ParamSink {
 public:
  ParamSink(std::string file, WeberPennParams& params, std::vector<std::string>& warnings)
      : file_(std::move(file)), p_(params), warnings_(warnings) {}

  [[noreturn]] void fail(int line, const std::string& what) const { throw ParseError(file_, line, what); }
  void warn(int line, const std::string& what) const {
    warnings_.push_back(fmt::format("{}:{}: warning: {}", file_, line, what));
  }

  // Sets parameter `name` (the paper's spelling, level prefix included) from `value`.
  void set(const std::string& name, const Value& value) {
    const int line = value.line;
    if (const auto it = seen_.find(name); it != seen_.end())
      fail(line, fmt::format("parameter '{}' given twice (first on line {})", name, it->second));
    seen_.emplace(name, line);

    if (name == "LeafShape") return set_leaf_shape(value, line);
    if (name == "reading") return set_reading(value, line);
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
    if (v.kind == Value::Kind::String) fail(line, fmt::format("'{}' must be a number, not \"{}\"", name, v.string));
    if (!v.is_number()) fail(line, fmt::format("'{}' must be a number", name));
    const double x = v.number();
    if (!std::isfinite(x)) fail(line, fmt::format("'{}' must be finite", name));
    if (integer && x != std::floor(x))
      fail(line, fmt::format("'{}' must be an integer, not {}", name, format_number(x)));
    if (x < lo || x > hi) {
      if (hi >= kInf)
        fail(line, fmt::format("'{}' must be at least {}, not {}", name, format_number(lo), format_number(x)));
      if (lo <= -kInf)
        fail(line, fmt::format("'{}' must be at most {}, not {}", name, format_number(hi), format_number(x)));
      fail(line, fmt::format("'{}' must be in [{}, {}], not {}", name, format_number(lo), format_number(hi),
                             format_number(x)));
    }
    return x;
  }

  // `reading = "paper" | "arbaro"`: which reading of the paper's ambiguous places (docs/weber_penn.md).
  void set_reading(const Value& v, int line) {
    if (v.kind == Value::Kind::String && v.string == "paper") {
      p_.reading = wp::Reading::Paper;
    } else if (v.kind == Value::Kind::String && v.string == "arbaro") {
      p_.reading = wp::Reading::Arbaro;
    } else {
      fail(line, fmt::format("'reading' must be \"paper\" or \"arbaro\", not {}",
                             v.kind == Value::Kind::String ? "\"" + v.string + "\"" : format_number(v.number())));
    }
  }

  // The paper's ids 0..5 (oval, triangle, oak3, maple3, maple5, leaflets3) or those names;
  // Arbaro's "disc"/"discN" mean oval, its "sphere" and "palm" are not flat outlines (warned).
  void set_leaf_shape(const Value& v, int line) {
    if (v.is_number()) {
      if (v.number() != std::floor(v.number()) || v.number() < 0 || v.number() > 5)
        fail(line,
             fmt::format("'LeafShape' must be an id 0..5 (oval, triangle, oak3, maple3, maple5, leaflets3), not {}",
                         format_number(v.number())));
      p_.leaf_shape = static_cast<LeafShape>(static_cast<int>(v.number()) + static_cast<int>(LeafShape::Oval));
      return;
    }
    if (v.string.rfind("disc", 0) == 0) {
      p_.leaf_shape = LeafShape::Oval;
      return;
    }
    if (v.string == "sphere" || v.string == "palm") {
      p_.leaf_shape = LeafShape::Oval;
      warn(line, fmt::format("Arbaro leaf shape \"{}\" is drawn as an oval leaf", v.string));
      return;
    }
    const std::optional<LeafShape> shape = leaf_shape_from_name(v.string);
    if (!shape || *shape == LeafShape::Rectangle)
      fail(line,
           fmt::format("unknown LeafShape \"{}\" (expected 0..5 or oval, triangle, oak3, maple3, maple5, leaflets3)",
                       v.string));
    p_.leaf_shape = *shape;
  }

  std::string file_;
  WeberPennParams& p_;
  std::vector<std::string>& warnings_;
  std::map<std::string, int> seen_;
};

bool is_level_table(const std::string& name) {
  return name.size() == 6 && name.rfind("level", 0) == 0 && name[5] >= '0' && name[5] <= '3';
}

}  // namespace

WeberPennParams WeberPennParams::create(const Params& params, std::vector<std::string>& warnings) {
  WeberPennParams p;
  ParamSink sink(params.file(), p, warnings);
  for (const std::string& name : params.unread_names()) {
    const ParamValue& value = *params.get(name);
    if (value.kind == ParamValue::Kind::Table) {
      if (!is_level_table(name))
        params.fail_at(value, fmt::format("unknown table [{}] (expected [level0] .. [level3])", name));
      const Params& level = *value.table;
      for (const std::string& lname : level.names()) {
        const ParamValue& lvalue = *level.get(lname);
        bool known = false;
        for (const LevelSpec& s : level_specs()) known = known || s.name == lname;
        if (!known) level.fail_at(lvalue, fmt::format("unknown level parameter '{}' in [{}]", lname, name));
        if (!lvalue.is_number() && lvalue.kind != ParamValue::Kind::String)
          level.fail_at(lvalue, fmt::format("'{}' must be a number", lname));
        sink.set(fmt::format("{}{}", name[5], lname), lvalue);
      }
      continue;
    }
    if (!value.is_number() && value.kind != ParamValue::Kind::String)
      params.fail_at(value, fmt::format("'{}' must be a number", name));
    sink.set(name, value);
  }
  if (p.asks_below_ground())
    warnings.push_back(
        fmt::format("{}: warning: 0DownAngle ± 0DownAngleV may point a trunk below the horizontal; "
                    "its stems and leaves are not kept above the ground",
                    params.file()));
  return p;
}

std::vector<std::string> weber_penn_parameter_names() {
  std::vector<std::string> names;
  for (const Spec& s : global_specs()) names.emplace_back(s.name);
  names.emplace_back("LeafShape");
  names.emplace_back("Smooth");
  names.emplace_back("reading");
  for (int level = 0; level <= 3; ++level)
    for (const LevelSpec& s : level_specs()) names.push_back(fmt::format("{}{}", level, s.name));
  return names;
}

}  // namespace sylva

#include "pipeline/study_design.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "core/rng.h"
#include "scenes/sections/scene_builder.h"
#include "scenes/toml_reader.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>

namespace sylva {

namespace {

// The most frames a study may plan (a grid's product included).
constexpr size_t kMaxStudyFrames = 10'000'000;

std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
      continue;
    }
    out += c;
  }
  out += '"';
  return out;
}

// A number as a study writes it: shortest text, rounded to 1e-6 (overrides and the manifest).
std::string number_text(double v) {
  const double r = std::round(v * 1e6) / 1e6;
  return fmt::format("{}", r == 0 ? 0.0 : r);
}

// A value of the study file as TOML text, for an override.
std::string toml_text(const ParamValue& v) {
  switch (v.kind) {
    case ParamValue::Kind::Bool:
      return v.boolean ? "true" : "false";
    case ParamValue::Kind::Integer:
      return std::to_string(v.integer);
    case ParamValue::Kind::Real:
      return fmt::format("{}", v.real);
    case ParamValue::Kind::String:
      return toml_string(v.string);
    case ParamValue::Kind::Array: {
      std::string out = "[";
      for (size_t i = 0; i < v.array.size(); ++i) out += fmt::format("{}{}", i ? ", " : "", toml_text(v.array[i]));
      return out + "]";
    }
    case ParamValue::Kind::Table: {
      std::string out = "{";
      bool first = true;
      for (const std::string& name : v.table->names()) {
        out += fmt::format("{}{} = {}", first ? " " : ", ", name, toml_text(*v.table->get(name)));
        first = false;
      }
      return out + " }";
    }
  }
  return {};
}

StudyNumber read_number(const Params& t, const char* key, double fallback, const std::vector<StudyFactor>& factors) {
  const ParamValue* v = t.get(key);
  if (v == nullptr) return {{}, fallback};
  if (v->kind != ParamValue::Kind::String) return {{}, t.number(key)};
  for (const StudyFactor& f : factors)
    if (f.name == v->string) return {v->string, 0};
  t.fail(key, fmt::format("'{}' names no factor (a number, or the name of a [[factors]] entry)", v->string));
}

StudyFactor read_factor(const Params& t, StudyDesign design) {
  t.check_keys({"name", "set", "values", "range", "integer"});
  StudyFactor f;
  f.name = t.string("name");
  if (f.name.empty() || f.name.find_first_of(",\"\n") != std::string::npos)
    t.fail("name", "a factor name must be non-empty, without commas, quotes or line breaks");
  f.set = t.string("set", "");
  f.integer = t.boolean("integer", false);
  if (const ParamValue* values = t.get("values")) {
    if (values->kind != ParamValue::Kind::Array || values->array.empty())
      t.fail("values", "'values' must be a non-empty array");
    for (const ParamValue& v : values->array) f.values.push_back(toml_text(v));
  }
  if (t.has("range")) {
    const std::vector<double> r = t.numbers("range");
    if (r.size() != 2 || !(r[0] <= r[1])) t.fail("range", "'range' must be [low, high] with low <= high");
    if (design != StudyDesign::latin_hypercube) t.fail("range", "'range' is for design = \"latin_hypercube\"");
    f.range = std::make_pair(r[0], r[1]);
  }
  if (f.values.empty() == !f.range.has_value()) t.fail("give a factor either 'values' or 'range'");
  return f;
}

void read_bindings(const Params& root, StudySpec& spec) {
  if (const Params* o = root.table("camera_orbit")) {
    o->check_keys({"target", "range", "aspect", "elevation", "aim_height", "heading"});
    CameraOrbit orbit;
    orbit.target = o->string("target");
    orbit.range_m = read_number(*o, "range", 0, spec.factors);
    if (orbit.range_m.factor.empty() && !(orbit.range_m.value > 0)) o->fail("range", "'range' must be positive");
    orbit.aspect_deg = read_number(*o, "aspect", 0, spec.factors);
    orbit.elevation_deg = read_number(*o, "elevation", 0, spec.factors);
    orbit.aim_height_m = read_number(*o, "aim_height", 1.0, spec.factors);
    orbit.heading_given = o->has("heading");
    orbit.heading_deg = read_number(*o, "heading", 0, spec.factors);
    spec.camera_orbit = orbit;
  }
  if (const Params* s = root.table("sun_time")) {
    s->check_keys({"latitude", "longitude", "year", "day", "hour", "utc_offset"});
    SunTime sun;
    sun.latitude_deg = read_number(*s, "latitude", 45, spec.factors);
    sun.longitude_deg = read_number(*s, "longitude", 0, spec.factors);
    sun.year = read_number(*s, "year", 2025, spec.factors);
    sun.day = read_number(*s, "day", 172, spec.factors);
    sun.hour = read_number(*s, "hour", 12, spec.factors);
    sun.clock = s->has("utc_offset");
    sun.utc_offset_h = read_number(*s, "utc_offset", 0, spec.factors);
    if (sun.clock && !s->has("longitude"))
      s->fail("utc_offset", "a clock time (utc_offset) needs the place's 'longitude' (degrees east)");
    spec.sun_time = sun;
  }
}

StudyDesign read_design(const Params& study) {
  const std::string design = study.string("design", "grid");
  if (design == "grid") return StudyDesign::grid;
  if (design == "list") return StudyDesign::list;
  if (design == "latin_hypercube") return StudyDesign::latin_hypercube;
  study.fail("design", "design must be \"grid\", \"list\" or \"latin_hypercube\"");
}

void read_study_table(const Params& study, const std::filesystem::path& file, StudySpec& spec) {
  study.check_keys({"scene", "output", "design", "samples", "seed", "png", "set"});
  spec.scene = study.file_path("scene");
  const std::filesystem::path dir = file.parent_path().empty() ? "." : file.parent_path();
  spec.output_dir = dir / study.string("output", file.stem().string() + "_frames");
  spec.design = read_design(study);
  spec.samples = static_cast<int>(study.integer("samples", 0, 0, static_cast<int64_t>(kMaxStudyFrames)));
  if (spec.design == StudyDesign::latin_hypercube && spec.samples == 0)
    study.fail("samples", "a latin_hypercube needs 'samples' (the number of frames)");
  if (spec.design != StudyDesign::latin_hypercube && study.has("samples"))
    study.fail("samples", "'samples' is for design = \"latin_hypercube\"");
  spec.seed = static_cast<uint64_t>(study.integer("seed", 1, 0, INT64_MAX));
  spec.png = study.boolean("png", false);
  if (study.has("set")) spec.set = study.strings("set");
}

}  // namespace

StudySpec load_study(const std::filesystem::path& file) {
  const std::string text = read_input_file(file, kMaxSceneFileBytes, "study file");
  TomlReader reader(file.string());
  const toml::table document = reader.parse(text);
  const std::filesystem::path dir = file.parent_path();
  const Params root =
      reader.to_params(document, "the study", [dir](const std::string& name) { return find_named_file(dir, name); });
  root.check_keys({"study", "factors", "camera_orbit", "sun_time"});
  StudySpec spec;
  spec.file = file;
  const Params* study = root.table("study");
  if (study == nullptr) root.fail("a study file needs a [study] table with the base `scene`");
  read_study_table(*study, file, spec);
  for (const Params* t : root.tables("factors")) {
    spec.factors.push_back(read_factor(*t, spec.design));
    for (size_t i = 0; i + 1 < spec.factors.size(); ++i)
      if (spec.factors[i].name == spec.factors.back().name)
        t->fail("name", "factor '" + spec.factors.back().name + "' is named twice");
  }
  read_bindings(root, spec);
  (void)design_values(spec);  // sizes and combinations checked now, before any work
  return spec;
}

namespace {

std::vector<std::vector<std::string>> grid_values(const StudySpec& spec) {
  size_t count = 1;
  for (const StudyFactor& f : spec.factors) {
    count *= f.values.size();
    if (count > kMaxStudyFrames)
      throw Error(fmt::format("{}: the grid has more than {} frames", spec.file.string(), kMaxStudyFrames));
  }
  std::vector<std::vector<std::string>> frames(count, std::vector<std::string>(spec.factors.size()));
  for (size_t i = 0; i < count; ++i) {
    size_t rest = i;
    for (size_t f = spec.factors.size(); f-- > 0;) {
      const std::vector<std::string>& values = spec.factors[f].values;
      frames[i][f] = values[rest % values.size()];
      rest /= values.size();
    }
  }
  return frames;
}

std::vector<std::vector<std::string>> list_values(const StudySpec& spec) {
  const size_t count = spec.factors.empty() ? 1 : spec.factors[0].values.size();
  for (const StudyFactor& f : spec.factors)
    if (f.values.size() != count)
      throw Error(
          fmt::format("{}: design = \"list\" needs the same number of values in every factor ('{}' has {}, "
                      "'{}' has {})",
                      spec.file.string(), spec.factors[0].name, count, f.name, f.values.size()));
  std::vector<std::vector<std::string>> frames(count, std::vector<std::string>(spec.factors.size()));
  for (size_t i = 0; i < count; ++i)
    for (size_t f = 0; f < spec.factors.size(); ++f) frames[i][f] = spec.factors[f].values[i];
  return frames;
}

// McKay, Beckman & Conover (1979): in each factor, frame i falls in stratum perm[i] of N equal
// strata, at a uniform position within it; each factor has its own permutation and jitter,
// drawn from hash_ids(seed, factor index).
std::vector<std::vector<std::string>> hypercube_values(const StudySpec& spec) {
  const auto n = static_cast<size_t>(spec.samples);
  std::vector<std::vector<std::string>> frames(n, std::vector<std::string>(spec.factors.size()));
  for (size_t f = 0; f < spec.factors.size(); ++f) {
    const StudyFactor& factor = spec.factors[f];
    Pcg32 rng(hash_ids(spec.seed, f, 0x1A7C));
    std::vector<size_t> stratum(n);
    std::iota(stratum.begin(), stratum.end(), size_t{0});
    for (size_t i = n; i-- > 1;) std::swap(stratum[i], stratum[static_cast<size_t>(rng.uniform_double() * (i + 1))]);
    for (size_t i = 0; i < n; ++i) {
      const double u = (static_cast<double>(stratum[i]) + rng.uniform_double()) / static_cast<double>(n);
      if (!factor.range) {
        frames[i][f] = factor.values[std::min(static_cast<size_t>(u * factor.values.size()), factor.values.size() - 1)];
        continue;
      }
      const auto [lo, hi] = *factor.range;
      const double v = lo + u * (hi - lo);
      frames[i][f] = factor.integer ? fmt::format("{}", static_cast<int64_t>(std::clamp(std::floor(v + 0.5), lo, hi)))
                                    : number_text(v);
    }
  }
  return frames;
}

}  // namespace

std::vector<std::vector<std::string>> design_values(const StudySpec& spec) {
  switch (spec.design) {
    case StudyDesign::grid:
      return grid_values(spec);
    case StudyDesign::list:
      return list_values(spec);
    case StudyDesign::latin_hypercube:
      return hypercube_values(spec);
  }
  return {};
}

namespace {

// Days from 2000-01-01 to 1 January of `year` (proleptic Gregorian).
int64_t days_to_new_year(int64_t year) {
  const auto leaps_before = [](int64_t y) { return (y - 1) / 4 - (y - 1) / 100 + (y - 1) / 400; };
  return 365 * (year - 2000) + leaps_before(year) - leaps_before(2000);
}

}  // namespace

// The U.S. Naval Observatory's "Approximate Solar Coordinates" (Astronomical Applications Dept.;
// the low-precision formulas of The Astronomical Almanac, section C): about 1′ in the sun's
// coordinates and a few seconds in the equation of time from 1950 to 2050. D is days from J2000.0
// (2000-01-01 12:00 UT); g the mean anomaly, q the mean longitude, L the apparent ecliptic
// longitude, ε the obliquity; the equation of time is q − RA, the hour angle
// 15° (UT − 12) + longitude + the equation of time.
SolarPosition solar_position(double latitude_deg, double longitude_deg, int year, double day_of_year, double hour_utc) {
  const double d = static_cast<double>(days_to_new_year(year)) + (day_of_year - 1.0) + (hour_utc - 12.0) / 24.0;
  const double g = glm::radians(357.529 + 0.98560028 * d);
  const double q = std::fmod(280.459 + 0.98564736 * d, 360.0);
  const double l = glm::radians(q + 1.915 * std::sin(g) + 0.020 * std::sin(2.0 * g));
  const double e = glm::radians(23.439 - 0.00000036 * d);
  const double ra_deg = glm::degrees(std::atan2(std::cos(e) * std::sin(l), std::cos(l)));
  const double decl = std::asin(std::sin(e) * std::sin(l));
  const double eot_deg = std::remainder(q - ra_deg, 360.0);
  const double hour_angle = glm::radians(15.0 * (hour_utc - 12.0) + longitude_deg + eot_deg);
  const double lat = glm::radians(latitude_deg);
  // East, north, up of the direction to the sun.
  const double east = -std::cos(decl) * std::sin(hour_angle);
  const double north = std::sin(decl) * std::cos(lat) - std::cos(decl) * std::cos(hour_angle) * std::sin(lat);
  const double up = std::sin(decl) * std::sin(lat) + std::cos(decl) * std::cos(hour_angle) * std::cos(lat);
  SolarPosition s;
  s.azimuth_deg = glm::degrees(std::atan2(east, north));
  if (s.azimuth_deg < 0) s.azimuth_deg += 360.0;
  s.elevation_deg = glm::degrees(std::asin(std::clamp(up, -1.0, 1.0)));
  s.equation_of_time_min = 4.0 * eot_deg;
  s.declination_deg = glm::degrees(decl);
  return s;
}

namespace {

double value_of(const StudySpec& spec, const StudyNumber& n, const std::vector<std::string>& values) {
  if (n.factor.empty()) return n.value;
  for (size_t f = 0; f < spec.factors.size(); ++f) {
    if (spec.factors[f].name != n.factor) continue;
    char* end = nullptr;
    const double v = std::strtod(values[f].c_str(), &end);
    if (values[f].empty() || *end != '\0' || !std::isfinite(v))
      throw Error(fmt::format("{}: factor '{}' must have numbers to place the camera or sun, not {}",
                              spec.file.string(), n.factor, values[f]));
    return v;
  }
  throw Error(fmt::format("{}: no factor '{}'", spec.file.string(), n.factor));
}

std::string vec3_text(const glm::dvec3& v) {
  return fmt::format("[{}, {}, {}]", number_text(v.x), number_text(v.y), number_text(v.z));
}

void add_orbit(const StudySpec& spec, const SceneFile& base, const std::vector<std::string>& values,
               std::vector<std::string>& overrides) {
  const CameraOrbit& orbit = *spec.camera_orbit;
  const TargetInfo* target = nullptr;
  for (const TargetInfo& t : base.targets)
    if (t.name == orbit.target) target = &t;
  if (target == nullptr)
    throw Error(fmt::format("{}: [camera_orbit] target '{}' is no [[targets]] name of {}", spec.file.string(),
                            orbit.target, spec.scene.string()));
  const double range = value_of(spec, orbit.range_m, values);
  if (!(range > 0)) throw Error(fmt::format("{}: [camera_orbit] range must be positive", spec.file.string()));
  const double heading = orbit.heading_given ? value_of(spec, orbit.heading_deg, values) : target->heading_deg;
  const double bearing = glm::radians(heading + value_of(spec, orbit.aspect_deg, values));
  const double elevation = glm::radians(value_of(spec, orbit.elevation_deg, values));
  const glm::dvec3 aim = glm::dvec3(target->position) + glm::dvec3(0, 0, value_of(spec, orbit.aim_height_m, values));
  glm::dvec3 eye = aim + range * glm::dvec3(std::sin(bearing) * std::cos(elevation),
                                            std::cos(bearing) * std::cos(elevation), std::sin(elevation));
  glm::dvec3 at = aim;
  if (base.camera_ground) {  // [camera] above_terrain: z above the ground under each point
    eye.z -= static_cast<double>(
        terrain_height(*base.camera_ground, Vec2(static_cast<float>(eye.x), static_cast<float>(eye.y))));
    at.z -= static_cast<double>(
        terrain_height(*base.camera_ground, Vec2(static_cast<float>(at.x), static_cast<float>(at.y))));
  }
  overrides.push_back("camera.position=" + vec3_text(eye));
  overrides.push_back("camera.target=" + vec3_text(at));
}

void add_sun(const StudySpec& spec, const std::vector<std::string>& values, std::vector<std::string>& overrides) {
  const SunTime& t = *spec.sun_time;
  const double longitude = value_of(spec, t.longitude_deg, values);
  const double hour = value_of(spec, t.hour, values);
  // Clock time in its zone, or local mean solar time: either way to UT.
  const double hour_utc = t.clock ? hour - value_of(spec, t.utc_offset_h, values) : hour - longitude / 15.0;
  const double year = value_of(spec, t.year, values);
  if (!(year >= 1 && year <= 9999))
    throw Error(fmt::format("{}: [sun_time] year must lie in [1, 9999], not {}", spec.file.string(), year));
  const SolarPosition s = solar_position(value_of(spec, t.latitude_deg, values), longitude,
                                         static_cast<int>(std::lround(year)), value_of(spec, t.day, values), hour_utc);
  overrides.push_back("sun.azimuth=" + number_text(s.azimuth_deg));
  overrides.push_back("sun.elevation=" + number_text(s.elevation_deg));
}

}  // namespace

std::vector<StudyFrame> plan_study(const StudySpec& spec, const SceneFile& base) {
  const std::vector<std::vector<std::string>> values = design_values(spec);
  std::vector<StudyFrame> frames(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    StudyFrame& frame = frames[i];
    frame.index = i;
    frame.values = values[i];
    frame.overrides = spec.set;
    for (size_t f = 0; f < spec.factors.size(); ++f)
      if (!spec.factors[f].set.empty()) frame.overrides.push_back(spec.factors[f].set + "=" + values[i][f]);
    if (spec.camera_orbit) add_orbit(spec, base, values[i], frame.overrides);
    if (spec.sun_time) add_sun(spec, values[i], frame.overrides);
    uint64_t h = hash_ids(hash_text(SYLVA_VERSION), hash_text(base.content_hash));
    for (const std::string& o : frame.overrides) h = hash_ids(h, hash_text(o));
    frame.id = hex64(h);
  }
  return frames;
}

}  // namespace sylva

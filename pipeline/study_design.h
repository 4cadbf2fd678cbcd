#pragma once
// A detection study's plan (docs/studies.md): a base scene and factors, combined as a full grid, an
// explicit list or a seeded Latin hypercube, into frames — each a list of `--set` overrides of the
// base scene (scenes/toml_reader.h) with a stable id, the hash of everything it is rendered from.
// Reading the study file and planning are pure (no rendering): pipeline/study.h renders the plan.

#include "scenes/scene_file.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

// One factor: a named dimension of the study. Its value goes to the override `set` (a scene key,
// `sun.elevation`, `targets.tank.heading`), and/or feeds [camera_orbit] or [sun_time] by name.
struct StudyFactor {
  std::string name;
  std::string set;                                 // empty: only read by [camera_orbit] / [sun_time]
  std::vector<std::string> values;                 // TOML value texts (grid, list; a hypercube picks among them)
  std::optional<std::pair<double, double>> range;  // a hypercube's continuous interval
  bool integer = false;                            // a hypercube's value is rounded (seeds)
};

// A number given in the study file or named after a factor (whose value must then be a number).
struct StudyNumber {
  std::string factor;  // empty: `value`
  double value = 0;
};

// The camera around a named [[targets]] entry of the base scene: at `range_m` (slant) from the aim
// point (the target's position raised by `aim_height_m`), `elevation_deg` above its horizontal,
// seen at `aspect_deg` from the target's front (clockwise from above: 90 = its right side), the
// target's front being its `heading` (a factor, else the base scene's). When the base scene's
// [camera] has above_terrain = true, the overrides give the camera's and the aim point's z as
// heights above the terrain under each, so the scene places them at these points.
struct CameraOrbit {
  std::string target;
  StudyNumber range_m, aspect_deg, elevation_deg, aim_height_m, heading_deg;
  bool heading_given = false;
};

// The sun at a place and time (solar_position): latitude and longitude (deg, north and east
// positive), year, day of the year (1–366) and `hour`: the clock time of the zone `utc_offset_h`
// hours from UTC when `clock` (utc_offset given), else the local mean solar time (12 = mean noon at
// the longitude; the sun crosses the meridian at 12 − the equation of time).
struct SunTime {
  StudyNumber latitude_deg, longitude_deg, year, day, hour, utc_offset_h;
  bool clock = false;
};

enum class StudyDesign { grid, list, latin_hypercube };

struct StudySpec {
  std::filesystem::path file;        // the study file
  std::filesystem::path scene;       // the base scene, resolved
  std::filesystem::path output_dir;  // resolved against the study file's folder
  StudyDesign design = StudyDesign::grid;
  int samples = 0;               // latin_hypercube: frames
  uint64_t seed = 1;             // latin_hypercube
  bool png = false;              // a preview per frame
  std::vector<std::string> set;  // overrides of every frame, first
  std::vector<StudyFactor> factors;
  std::optional<CameraOrbit> camera_orbit;
  std::optional<SunTime> sun_time;
};

// Reads a study file; every mistake is a ParseError `file:line: what was expected`.
StudySpec load_study(const std::filesystem::path& file);

// Each frame's value of each factor (TOML text), in frame order: the grid with the first factor
// slowest; the list in order (every factor the same number of values); the hypercube with one
// stratum per frame in every factor, permuted and jittered from `seed` (McKay, Beckman & Conover
// 1979), a factor with `values` choosing among them by stratum.
std::vector<std::vector<std::string>> design_values(const StudySpec& spec);

struct StudyFrame {
  size_t index = 0;
  std::string id;                      // 16 hex digits: the hash of the frame's inputs
  std::vector<std::string> values;     // per factor
  std::vector<std::string> overrides;  // every --set of the frame, in order (the study's first)
};

// The frames of the study over its base scene (loaded with the study's `set`): overrides from the
// factors, then the camera (camera.position, camera.target) and sun (sun.azimuth, sun.elevation)
// they place. The id hashes Sylva's version, the base scene's content hash (its text, every file
// it reads, the study's overrides) and the frame's overrides, so a frame whose inputs change gets
// a new id and is rendered again.
std::vector<StudyFrame> plan_study(const StudySpec& spec, const SceneFile& base);

// The sun at a place and time: compass azimuth and elevation (deg, geometric: no refraction), and the
// equation of time (minutes, apparent minus mean solar time). `hour_utc` may lie outside [0, 24).
struct SolarPosition {
  double azimuth_deg = 0, elevation_deg = 0, equation_of_time_min = 0, declination_deg = 0;
};
SolarPosition solar_position(double latitude_deg, double longitude_deg, int year, double day_of_year, double hour_utc);

}  // namespace sylva

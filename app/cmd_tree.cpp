// `sylva tree`: generate one tree from a species file, print statistics, export OBJ/PLY.

#include "app/commands.h"
#include "core/error.h"
#include "core/output_paths.h"
#include "geometry/mesh_io.h"
#include "geometry/solids/solid_mesh.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/tree_stats.h"
#include "scenes/species.h"
#include "scenes/tree_lod.h"

#include <fmt/core.h>

#include <chrono>
#include <cstdlib>
#include <memory>

namespace sylva {
namespace {

struct TreeArgs {
  std::string species;
  uint64_t seed = 1;
  float time_s = 0.0f;
  std::string wind;
  float quality = 1.0f;
  std::string obj, ply;
  bool stats = false;
  bool lod = false;
};

// "SPEED,GUST" (or "SPEED") → {speed, gust}.
std::pair<float, float> parse_wind(const std::string& text) {
  const size_t comma = text.find(',');
  const std::string a = text.substr(0, comma);
  const std::string b = comma == std::string::npos ? "0" : text.substr(comma + 1);
  char* end_a = nullptr;
  char* end_b = nullptr;
  const float speed = std::strtof(a.c_str(), &end_a);
  const float gust = std::strtof(b.c_str(), &end_b);
  if (a.empty() || b.empty() || *end_a != '\0' || *end_b != '\0' || !(speed >= 0.0f) || !(gust >= 0.0f))
    throw Error(fmt::format("--wind: expected SPEED,GUST (two non-negative numbers), got \"{}\"", text));
  return {speed, gust};
}

// Every solid of a tree polygonised into one mesh.
TriangleMesh solid_tree_mesh(const TreeModel& model) {
  TriangleMesh out;
  for (const HalfSpaceSolid& s : model.solids) append_mesh(out, solid_surface_mesh(s));
  return out;
}

// A tree made of half-space solids (Fournier–Grindal): statistics per solid, OBJ of its surface.
int run_solid_tree(const TreeArgs& a, const Species& species, const TreeModel& model, double ms) {
  if (!a.ply.empty()) throw Error("--ply: a half-space tree is written with --obj only");
  if (!a.obj.empty()) write_obj(a.obj, solid_tree_mesh(model));
  if (!a.stats) return 0;
  std::string solids;
  for (const HalfSpaceSolid& s : model.solids) {
    const PolytopeFaces faces = polytope_faces(s.planes, kSolidExtentM);
    solids += fmt::format(
        "{}    {{\"part\": \"{}\", \"planes\": {}, \"faces\": {}, \"volume_m3\": {:.6g}, \"displacement_m\": {}, "
        "\"bounds_lo\": [{:.4f}, {:.4f}, {:.4f}], \"bounds_hi\": [{:.4f}, {:.4f}, {:.4f}]}}",
        solids.empty() ? "" : ",\n", s.material_slot == 0 ? "trunk" : "crown", s.planes.size(), faces.polygons.size(),
        polytope_volume(faces), s.displacement_m, s.bounds.lo.x, s.bounds.lo.y, s.bounds.lo.z, s.bounds.hi.x,
        s.bounds.hi.y, s.bounds.hi.z);
  }
  fmt::print(
      "{{\n  \"species\": \"{}\",\n  \"seed\": {},\n  \"generation_ms\": {:.3f},\n  \"solids\": [\n{}\n  ]\n}}\n",
      species.name, a.seed, ms, solids);
  return 0;
}

// The levels of detail (docs/lod.md) as a Markdown table.
void print_lod_levels(const std::vector<LodLevelReport>& levels) {
  fmt::print(
      "| level | r2 | tube segments (0/1/2) | line segments (0/1/2) | triangles | leaf quads | leaf discs | curves | "
      "leaf area m² | geometry KiB | BVH KiB | build ms "
      "|\n|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (size_t k = 0; k < levels.size(); ++k) {
    const LodLevelReport& r = levels[k];
    const LodCounts& c = r.counts;
    fmt::print("| {} | {:g} | {}/{}/{} | {}/{}/{} | {} | {} | {} | {} | {:.3f} | {:.0f} | {:.0f} | {:.1f} |\n", k, r.r2,
               c.tube_segments[0], c.tube_segments[1], c.tube_segments[2], c.line_segments[0], c.line_segments[1],
               c.line_segments[2], r.triangles, r.leaf_quads, r.discs, r.curves, r.leaf_area_m2,
               static_cast<double>(r.geometry_bytes) / 1024.0, static_cast<double>(r.bvh_bytes) / 1024.0, r.build_ms);
  }
}

int run_tree(const TreeArgs& a) {
  const std::vector<OutputFile> outputs{{"--obj", a.obj}, {"--ply", a.ply}};
  check_outputs(outputs, {a.species});
  const Species species = load_species(a.species);
  // A TREE-MAKER species in TOML reads its template too.
  if (const auto* tm = std::get_if<TreeMakerTemplate>(&species.model)) check_outputs(outputs, {a.species, tm->source});
  for (const std::string& w : species.warnings) fmt::print(stderr, "{}\n", w);
  TreeOptions options;
  options.time_s = a.time_s;
  options.quality = a.quality;
  if (!a.wind.empty()) std::tie(options.wind_speed, options.wind_gust) = parse_wind(a.wind);

  const auto start = std::chrono::steady_clock::now();
  const TreeModel model = make_species_model(species, a.seed, options);
  if (!model.solids.empty()) {
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return run_solid_tree(a, species, model, ms);
  }
  TreeMeshOptions mesh_options;
  mesh_options.quality = options.quality;
  const TreeMesh mesh = mesh_species_model(species, model, mesh_options);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  if (!a.obj.empty()) write_obj(a.obj, mesh);
  if (!a.ply.empty()) write_ply(a.ply, mesh);
  if (a.stats) fmt::print("{}", tree_stats_json(compute_tree_stats(model, mesh), species.name, a.seed, ms));
  if (a.lod) print_lod_levels(report_lod_levels(model, mesh, mesh_options));
  return 0;
}

}  // namespace

CommandRun add_tree_command(CLI::App& parent) {
  auto args = std::make_shared<TreeArgs>();
  CLI::App* cmd = parent.add_subcommand("tree", "Generate one tree from a species file (statistics, OBJ/PLY export)");
  cmd->add_option("species", args->species, "Species file (.toml, Arbaro .xml, .lsys, .grammar, .tmpl, .hbtree)")
      ->required();
  cmd->add_option("--seed", args->seed, "Tree seed (same seed, same tree)")->check(kUint64)->capture_default_str();
  cmd->add_option("--time", args->time_s, "Time in seconds for wind sway")->check(kFiniteNumber)->capture_default_str();
  cmd->add_option("--wind", args->wind, "Wind SPEED,GUST (Weber & Penn §4.7)");
  cmd->add_option("--quality", args->quality, "Quality factor (§4.5): leaf count and mesh resolution")
      ->check(kFiniteNumber & CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option("--obj", args->obj, "Write the mesh as Wavefront OBJ (half-space crowns: their polygonised surface)");
  cmd->add_option("--ply", args->ply, "Write the mesh as binary PLY");
  cmd->add_flag("--stats", args->stats, "Print statistics as JSON");
  cmd->add_flag("--lod", args->lod,
                "Print the levels of detail (Weber & Penn §5, docs/lod.md): elements, leaf area, memory and BVH size");
  return [args] { return run_tree(*args); };
}

}  // namespace sylva

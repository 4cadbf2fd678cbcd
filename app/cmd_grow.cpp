// `sylva grow`: grow a Hart-Baker tree year by year with the light-view pass (docs/hart_baker.md),
// export it, its growth rings and its state.

#include "app/commands.h"
#include "core/error.h"
#include "core/image.h"
#include "core/progress.h"
#include "geometry/mesh_io.h"
#include "geometry/trees/hart_baker/surface.h"
#include "geometry/trees/tree_mesher.h"
#include "pipeline/growth_frames.h"
#include "render/renderer.h"
#include "scenes/hart_baker_growth.h"
#include "scenes/scene_file.h"
#include "scenes/species.h"
#include "scenes/species/hart_baker_state_file.h"

#include <fmt/core.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>

#include <unistd.h>

namespace sylva {
namespace {

struct GrowArgs {
  std::string species;
  int years = -1;
  uint64_t seed = 1;
  std::string obj, save, frames, obstacles;
  std::vector<std::string> rings;
  std::vector<int32_t> prune;
  bool stats = false;
};

// Statistics of a state as JSON (for --stats).
std::string grow_stats_json(const std::string& name, const HartBakerTree& tree, const HartBakerParams& params,
                            const std::vector<float>& light, int shed, double seconds) {
  const LimbSums s = compute_limb_sums(tree, params, light);
  int alive = 0;
  float top = 0.0f;
  for (size_t i = 0; i < tree.size(); ++i) {
    if (!tree.alive[i]) continue;
    ++alive;
    top = std::max(top, (tree.base[i] + tree.direction[i] * tree.length_m[i]).z);
  }
  double leaf_area = 0.0, lit = 0.0;
  for (size_t i = 0; i < tree.size(); ++i) {
    leaf_area += s.leaf_area_m2[i];
    lit += light.empty() ? 0.0 : light[i];
  }
  const double offset = std::hypot(s.X[0].x, s.X[0].y);
  return fmt::format(
      "{{\n  \"species\": \"{}\",\n  \"seed\": {},\n  \"year\": {},\n  \"limbs\": {},\n  \"limbs_ever\": {},\n"
      "  \"limbs_shed\": {},\n  \"height_m\": {:.4f},\n  \"trunk_radius_m\": {:.5f},\n  \"mass_kg\": {:.4f},\n"
      "  \"centre_of_mass_m\": [{:.4f}, {:.4f}, {:.4f}],\n  \"centre_of_mass_offset_m\": {:.5f},\n"
      "  \"leaf_area_m2\": {:.4f},\n  \"intercepted_m2\": {:.4f},\n  \"seconds\": {:.3f}\n}}\n",
      name, tree.seed, tree.year, alive, tree.size(), shed, top, tree.radius_m[0], s.M[0], s.X[0].x, s.X[0].y, s.X[0].z,
      offset, leaf_area, lit, seconds);
}

// Refuses a frames directory that cannot be made or written before any growing is done.
void check_frames_dir(const std::filesystem::path& dir) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
    throw Error(fmt::format("--frames: {} exists and is not a directory", dir.string()));
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(fmt::format("--frames: cannot create {}: {}", dir.string(), ec.message()));
  if (::access(dir.c_str(), W_OK) != 0) throw Error(fmt::format("--frames: {} is not writable", dir.string()));
}

int run_grow(const GrowArgs& a) {
  // A saved state continues from where it was saved; a species starts from the seedling.
  const std::filesystem::path input(a.species);
  const bool is_state = input.extension() == ".hbtree";
  std::optional<HartBakerStateFile> state;
  if (is_state) state = load_hart_baker_state(input);
  const std::filesystem::path species_file = is_state ? state->species : input;
  const Species species = load_species(species_file);
  for (const std::string& w : species.warnings) fmt::print(stderr, "{}\n", w);
  const HartBakerParams* found = std::get_if<HartBakerParams>(&species.model);
  if (!found)
    throw Error(
        fmt::format("{}: sylva grow needs a Hart-Baker species (model = \"hart-baker\") or a saved .hbtree state",
                    species_file.string()));
  const HartBakerParams params = *found;
  HartBakerTree tree = is_state ? std::move(state->tree) : make_hart_baker_seedling(params, a.seed);
  for (const int32_t id : a.prune) prune_hart_baker_limb(tree, id);
  const int years = a.years >= 0 ? a.years : (is_state ? 0 : params.years);

  const LightViewGeometry obstacles = a.obstacles.empty() ? LightViewGeometry() : scene_obstacles(a.obstacles);
  if (!a.frames.empty()) check_frames_dir(a.frames);
  std::vector<HartBakerTree> frame_states;
  int shed = 0;
  const auto start = std::chrono::steady_clock::now();
  {
    Progress progress("grow", static_cast<uint64_t>(years), true, "years");
    grow_hart_baker(tree, params, years, obstacles, [&](const HartBakerTree& t, const GrowthReport& report) {
      shed += report.shed;
      if (!a.frames.empty()) {
        write_obj(std::filesystem::path(a.frames) / fmt::format("year_{:03d}.obj", t.year),
                  make_hart_baker_mesh(hart_baker_tree_model(t, params), params));
        frame_states.push_back(t);
      }
      progress.add(1);
    });
    progress.finish();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_growth_frames(a.frames, frame_states, params);

  if (!a.obj.empty()) write_obj(a.obj, make_hart_baker_mesh(hart_baker_tree_model(tree, params), params));
  if (!a.save.empty()) {
    // The state names its species relative to where it is saved, when it can.
    const std::filesystem::path save(a.save);
    const std::filesystem::path base = std::filesystem::absolute(save).parent_path();
    std::filesystem::path rel = std::filesystem::absolute(species_file).lexically_relative(base);
    if (rel.empty()) rel = std::filesystem::absolute(species_file);
    write_text_file(save, format_hart_baker_state(tree, rel));
  }
  if (!a.rings.empty()) {
    char* end = nullptr;
    const float height = std::strtof(a.rings[0].c_str(), &end);
    if (end == a.rings[0].c_str() || *end != '\0' || !(height >= 0.0f))
      throw Error(fmt::format("--rings: expected a height in metres ≥ 0, got \"{}\"", a.rings[0]));
    write_trunk_rings(a.rings[1], tree, params, height);
  }
  if (a.stats) {
    // The light of the grown tree, averaged over more directions than a year's sample.
    HartBakerParams measure = params;
    measure.light.samples = std::max(measure.light.samples, 16);
    const std::vector<float> light = hart_baker_light(tree, measure, obstacles);
    fmt::print("{}", grow_stats_json(species.name, tree, params, light, shed, seconds));
  }
  return 0;
}

}  // namespace

CommandRun add_grow_command(CLI::App& parent) {
  auto args = std::make_shared<GrowArgs>();
  CLI::App* cmd = parent.add_subcommand(
      "grow", "Grow a Hart-Baker tree year by year with the light-view pass (docs/hart_baker.md)");
  cmd->add_option("species", args->species, "Hart-Baker species (.toml) or a saved state (.hbtree) to continue")
      ->required();
  cmd->add_option("--years", args->years, "Years to grow (default: the species' `years`; 0 for a saved state)")
      ->check(CLI::Range(0, 500));
  cmd->add_option("--seed", args->seed, "Tree seed (a saved state keeps its own)")->capture_default_str();
  cmd->add_option("--obj", args->obj, "Write the grown tree as Wavefront OBJ");
  cmd->add_flag("--stats", args->stats, "Print statistics as JSON");
  cmd->add_option("--rings", args->rings, "HEIGHT_M RINGS.png: trunk cross-section and ring widths (RINGS.csv)")
      ->expected(2);
  cmd->add_option("--obstacles", args->obstacles, "Scene file whose meshes and trees shade the tree (at the origin)");
  cmd->add_option("--save", args->save, "Save the state (.hbtree) to continue growing or use in a scene");
  cmd->add_option("--frames", args->frames,
                  "Directory for one OBJ and one path-traced preview per year grown (year_NNN.obj, year_NNN.png)");
  cmd->add_option("--prune", args->prune, "Limb ids to cut (with what they carry) before growing (§6.1)");
  return [args] { return run_grow(*args); };
}

}  // namespace sylva

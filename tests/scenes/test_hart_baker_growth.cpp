// The Hart–Baker growth loop (scenes/hart_baker_growth.h): the light-view geometry of a tree, saved
// states that continue growing bit for bit, species and state files as scene species, and the
// behaviour of the paper's Figure 1 (a balanced tree stands over its trunk; a phototropic tree
// gathers comparable light with far fewer branches).

#include "core/error.h"
#include "geometry/trees/hart_baker/rings.h"
#include "geometry/trees/hart_baker/surface.h"
#include "scenes/hart_baker_growth.h"
#include "scenes/scene_file.h"
#include "scenes/species.h"
#include "scenes/species/hart_baker_state_file.h"

#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

namespace sylva {
namespace {

HartBakerParams small_species() {
  HartBakerParams p;
  p.light.resolution = 128;
  return p;
}

TEST(HartBakerGrowth, LightGeometryTagsLeavesWithTheirLimb) {
  const HartBakerParams p = small_species();
  const HartBakerTree t = grow_hart_baker_tree(p, 2, 5, {});
  LightViewGeometry obstacle;
  obstacle.add_quad(Vec3(-1, -1, -5), Vec3(1, -1, -5), Vec3(1, 1, -5), Vec3(-1, 1, -5), -1);
  const LightViewGeometry g = hart_baker_light_geometry(t, p, Vec3(0, 0, 1), obstacle);
  const TreeLeaves leaves = hart_baker_leaves(t, p);
  size_t alive = 0;
  for (const uint8_t a : t.alive) alive += a;
  ASSERT_EQ(g.triangle_count(), 2 * (1 + alive + leaves.size()));
  std::set<int32_t> leaf_items;
  for (size_t k = 0; k < g.triangle_count(); ++k)
    if (g.items[k] >= 0) leaf_items.insert(g.items[k]);
  std::set<int32_t> expected(leaves.stem.begin(), leaves.stem.end());
  EXPECT_EQ(leaf_items, expected);
  // The light reaches every limb with leaves on a lone young tree from straight above.
  const std::vector<float> light = intercepted_area(render_light_view(g, Vec3(0, 0, 1), 256), t.size());
  double total = 0.0;
  for (const float a : light) total += a;
  EXPECT_GT(total, 0.0);
}

TEST(HartBakerGrowth, SavedStateContinuesBitForBit) {
  const HartBakerParams p = small_species();
  const HartBakerTree straight = grow_hart_baker_tree(p, 7, 9, {});
  HartBakerTree first = grow_hart_baker_tree(p, 7, 5, {});
  const std::string text = format_hart_baker_state(first, "species.toml");
  HartBakerStateFile read = parse_hart_baker_state(text, "tree.hbtree");
  EXPECT_EQ(read.species, std::filesystem::path("species.toml"));
  EXPECT_EQ(format_hart_baker_state(read.tree, "species.toml"), text);
  grow_hart_baker(read.tree, p, 4, {});
  EXPECT_EQ(format_hart_baker_state(read.tree, "x"), format_hart_baker_state(straight, "x"));
}

TEST(HartBakerGrowth, StateFileErrorsNameTheLine) {
  const HartBakerTree t = grow_hart_baker_tree(small_species(), 1, 2, {});
  const std::string good = format_hart_baker_state(t, "s.toml");
  auto error_line = [](const std::string& text) {
    try {
      parse_hart_baker_state(text, "t.hbtree");
    } catch (const ParseError& e) {
      return e.line();
    }
    return -1;
  };
  EXPECT_EQ(error_line("not a state\n"), 1);
  EXPECT_EQ(error_line(good + "limb 0 1 1 0 0 0 0 0 0 1 1 0.1 0 1 0 0 nope\n"),
            static_cast<int>(std::count(good.begin(), good.end(), '\n')) + 1);
  EXPECT_EQ(error_line(good + "twig 3\n"), static_cast<int>(std::count(good.begin(), good.end(), '\n')) + 1);
  EXPECT_EQ(error_line(
                "sylva-hart-baker-state 1\nspecies s.toml\nseed 1\nyear 0\nlimb 3 0 1 0 0 0 0 0 0 1 1 0.1 0 1 0 0 0\n"),
            5);
  EXPECT_GT(error_line("sylva-hart-baker-state 1\nseed 1\n"), 0);
}

using HartBakerFiles = test::TempDirTest;

TEST_F(HartBakerFiles, SpeciesAndStateFilesAreSceneSpecies) {
  const std::filesystem::path species = dir_ / "oak.toml";
  { std::ofstream(species) << "model = \"hart-baker\"\nname = \"Test oak\"\nyears = 4\n[light]\nresolution = 96\n"; }
  const Species s = load_species(species);
  ASSERT_TRUE(std::holds_alternative<HartBakerParams>(s.model));
  const TreeModel grown = make_species_model(s, 3);
  EXPECT_GT(grown.stems.size(), 1u);
  // A state saved beside it names it relatively and reads back as the same tree.
  const HartBakerParams& p = std::get<HartBakerParams>(s.model);
  const HartBakerTree t = grow_hart_baker_tree(p, 3, 4, {});
  { std::ofstream(dir_ / "oak.hbtree") << format_hart_baker_state(t, "oak.toml"); }
  const Species state = load_species(dir_ / "oak.hbtree");
  const TreeModel from_state = make_species_model(state, 999);  // a saved tree ignores the seed
  EXPECT_EQ(from_state.sections.positions, grown.sections.positions);
  EXPECT_NE(state.name.find("year 4"), std::string::npos);
  { std::ofstream(dir_ / "bad.toml") << "model = \"hart-baker\"\nbuds_per_node = 2\nbranch_angel_deg = 30\n"; }
  try {
    load_species(dir_ / "bad.toml");
    FAIL() << "a misspelt key must be rejected";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3);
  }
}

TEST_F(HartBakerFiles, SurfaceAndBarkKeysReachTheSceneMesh) {
  // The species' [bark] kind and [surface] blend choose what mesh_species_model draws; a bad kind is
  // reported at its line.
  const std::string head = "model = \"hart-baker\"\nyears = 6\n[light]\nresolution = 64\n";
  { std::ofstream(dir_ / "plain.toml") << head << "[surface]\nblend = false\n"; }
  {
    std::ofstream(dir_ / "spotted.toml")
        << head << "[surface]\njoint_min_radius_m = 0.0\n[bark]\nkind = \"spotted\"\nmin_radius_m = 0.0\n";
  }
  const Species plain = load_species(dir_ / "plain.toml");
  const Species spotted = load_species(dir_ / "spotted.toml");
  const TreeModel model = make_species_model(plain, 2);
  TreeMeshOptions options;
  options.leaves = false;
  const TreeMesh tubes = mesh_species_model(plain, model, options);
  EXPECT_EQ(tubes.stems.triangles, make_tree_mesh(model, options).stems.triangles);
  const TreeMesh dressed = mesh_species_model(spotted, model, options);
  const TriangleMesh bark = hart_baker_bark(model, std::get<HartBakerParams>(spotted.model));
  EXPECT_GT(bark.triangles.size(), 0u);
  EXPECT_GT(dressed.stems.triangles.size(), tubes.stems.triangles.size() + bark.triangles.size());
  { std::ofstream(dir_ / "bad_bark.toml") << head << "[bark]\nspacing_m = 0.02\nkind = \"stripy\"\n"; }
  try {
    load_species(dir_ / "bad_bark.toml");
    FAIL() << "an unknown bark kind must be rejected";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 7);
  }
}

TEST(HartBakerGrowth, RingsRecordEveryYearAtTheHeight) {
  const HartBakerParams p = small_species();
  const HartBakerTree t = grow_hart_baker_tree(p, 4, 10, {});
  const TrunkRings rings = trunk_rings(t, p, 0.3f);
  ASSERT_EQ(rings.size(), 10u);  // the seedling is already taller than 0.3 m
  for (size_t k = 1; k < rings.size(); ++k) {
    EXPECT_GT(rings.radius_m[k], rings.radius_m[k - 1]);
    // Nested: the ring centre never moves by more than the ring's width.
    EXPECT_LE(glm::length(rings.centre_m[k] - rings.centre_m[k - 1]),
              rings.radius_m[k] - rings.radius_m[k - 1] + 1e-6f);
  }
  const std::string csv = ring_widths_csv(rings);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 11);
  EXPECT_TRUE(trunk_rings(t, p, 1000.0f).size() == 0);
}

TEST(HartBakerGrowth, SceneTreesGrowForTheirYears) {
  const std::string head =
      "[materials.bark]\ntype = \"diffuse\"\nreflectance = 0.3\n[materials.leaf]\ntype = \"leaf\"\n"
      "reflectance = 0.1\ntransmittance = 0.1\n";
  auto tree = [](int years) {
    return "[[trees]]\nspecies = \"../species/hart_baker_broadleaf.toml\"\nbark = \"bark\"\nleaf = \"leaf\"\n"
           "years = " +
           std::to_string(years) + "\n";
  };
  const SceneFile f = parse_scene(head + tree(3) + tree(6) + tree(3), "grown.toml", SYLVA_SOURCE_DIR "/data/examples");
  ASSERT_EQ(f.scene.instances.size(), 3u);
  EXPECT_EQ(f.scene.instances[0].prototype, f.scene.instances[2].prototype);  // same age, one mesh
  const auto& young = f.scene.prototypes[f.scene.instances[0].prototype];
  const auto& older = f.scene.prototypes[f.scene.instances[1].prototype];
  EXPECT_GT(older.triangles.triangles.size(), young.triangles.triangles.size());
  try {
    parse_scene(head + tree(3) + "years = 4\n", "grown.toml", SYLVA_SOURCE_DIR "/data/examples");
    FAIL() << "a repeated key must be rejected";
  } catch (const ParseError& e) {
    EXPECT_GT(e.line(), 0);
  }
  EXPECT_THROW(parse_scene(head + tree(501), "grown.toml", SYLVA_SOURCE_DIR "/data/examples"), ParseError);
}

TEST(HartBakerGrowth, ExampleSceneLoads) {
  const SceneFile f = load_scene_file(SYLVA_SOURCE_DIR "/data/examples/grown.toml");
  EXPECT_EQ(f.scene.instances.size(), 7u);  // ground, wall, five trees
}

// Figure 1 of the paper, measured: mean over seeds.
struct Outcome {
  double com_offset_m = 0, light = 0, branches = 0, mass_kg = 0;
  double branch_mass_kg = 0;  // the living limbs off the trunk's axis (order ≥ 1)
};

// The light measure of §6.1, the same for every tree: the share of a fixed window's pixels that
// show a leaf of the tree (the paper's "percentage of pixels"), averaged over 24 directions from
// the growth pass's sun and sky distribution. The window (the face toward the light of a 14 m
// cube standing on the ground about the trunk) holds every 12-year crown of these seeds from every
// direction, at 512 pixels across (2.7 cm, under half a leaf's width), so both trees are seen at
// the same resolution, unlike each crown's own bounding square.
constexpr float kMeasureWindowM = 14.0f;

Outcome grow_and_measure(HartBakerParams p, uint64_t seed, int years) {
  const HartBakerTree t = grow_hart_baker_tree(p, seed, years, {});
  HartBakerParams lit = p;
  lit.phototropism = true;
  lit.light.samples = 24;
  lit.light.window_m = kMeasureWindowM;
  lit.light.resolution = 512;
  const std::vector<float> light = hart_baker_light(t, lit, {});
  const LimbSums s = compute_limb_sums(t, lit, light);
  Outcome o;
  o.com_offset_m = std::hypot(s.X[0].x, s.X[0].y);
  o.light = s.P[0] / (kMeasureWindowM * kMeasureWindowM);
  o.mass_kg = s.M[0];
  for (size_t i = 1; i < t.size(); ++i) o.branches += t.alive[i];
  for (size_t i = 0; i < t.size(); ++i)
    if (t.alive[i] && t.order[i] > 0) o.branch_mass_kg += s.m[i];
  return o;
}

// Fig. 1's trees are bushy: a genotype whose lateral buds nearly all break (bud_break 0.95), so
// the genetic crown shades its own inside, grown 20 years. Four light directions a year (§4.1
// allows several; the paper draws one): with one, a limb's lit fraction is a single direction's
// verdict, smoothed over two years, and shedding kills limbs lit from most of the sky.
TEST(HartBakerGrowth, Figure1BalanceAndPhototropism) {
  HartBakerParams genetic = small_species();
  genetic.bud_break = 0.95f;
  genetic.light.samples = 4;
  genetic.balance = false;
  genetic.phototropism = false;
  HartBakerParams balanced = genetic;
  balanced.balance = true;
  HartBakerParams phototropic = balanced;
  phototropic.phototropism = true;
  const int years = 20;
  constexpr int kSeeds = 4;
  Outcome g, b, l;
  double light_per_branch = 0.0;  // mean over seeds of (light ratio / branch ratio)
  int sheds_more_than_it_loses = 0;
  for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const Outcome og = grow_and_measure(genetic, seed, years), ob = grow_and_measure(balanced, seed, years),
                  ol = grow_and_measure(phototropic, seed, years);
    g.com_offset_m += og.com_offset_m / kSeeds;
    b.com_offset_m += ob.com_offset_m / kSeeds;
    l.com_offset_m += ol.com_offset_m / kSeeds;
    g.light += og.light / kSeeds;
    l.light += ol.light / kSeeds;
    g.branches += og.branches / kSeeds;
    l.branches += ol.branches / kSeeds;
    g.mass_kg += og.mass_kg / kSeeds;
    l.mass_kg += ol.mass_kg / kSeeds;
    g.branch_mass_kg += og.branch_mass_kg / kSeeds;
    l.branch_mass_kg += ol.branch_mass_kg / kSeeds;
    std::printf("seed %d: window covered genetic %.3f phototropic %.3f; branches %.0f, %.0f; mass %.1f, %.1f kg\n",
                static_cast<int>(seed), og.light, ol.light, og.branches, ol.branches, og.mass_kg, ol.mass_kg);
    const double per_branch = (ol.light / og.light) / (ol.branches / og.branches);
    light_per_branch += per_branch / kSeeds;
    sheds_more_than_it_loses += per_branch > 1.5;
  }
  RecordProperty("com_offset_genetic_m", std::to_string(g.com_offset_m));
  RecordProperty("com_offset_balanced_m", std::to_string(b.com_offset_m));
  RecordProperty("light_ratio", std::to_string(l.light / g.light));
  RecordProperty("branch_ratio", std::to_string(l.branches / g.branches));
  RecordProperty("mass_ratio", std::to_string(l.mass_kg / g.mass_kg));
  RecordProperty("branch_mass_ratio", std::to_string(l.branch_mass_kg / g.branch_mass_kg));
  std::printf(
      "Figure 1: centre of mass offset genetic %.4f m, balanced %.4f m, phototropic %.4f m; phototropic/genetic "
      "light %.3f, branches %.3f, mass %.3f (branches' %.3f), light per branch %.3f\n",
      g.com_offset_m, b.com_offset_m, l.com_offset_m, l.light / g.light, l.branches / g.branches, l.mass_kg / g.mass_kg,
      l.branch_mass_kg / g.branch_mass_kg, light_per_branch);
  // The balanced tree stands over its trunk: measured 0.20× the genetic tree's offset (seeds 1–6).
  EXPECT_LT(b.com_offset_m, 0.5 * g.com_offset_m);
  // Phototropism (Fig. 1c): measured over seeds 1–6, the phototropic tree keeps 0.86 of the genetic
  // tree's light (0.81–0.90 per seed) with 0.33 of its branches (0.29–0.36) — the paper's "about
  // the same light with ~25 % of the branches" — and 0.69 of its mass, 0.68 of its branches' mass
  // (the paper: ~25 %; ours grows from its light, docs/hart_baker.md "Figure 1"). Bounds about three standard errors of
  // the four-seed means away.
  EXPECT_GT(l.light, 0.75 * g.light);
  EXPECT_LT(l.branches, 0.45 * g.branches);
  EXPECT_GT(light_per_branch, 2.0);
  EXPECT_EQ(sheds_more_than_it_loses, kSeeds);
}

}  // namespace
}  // namespace sylva

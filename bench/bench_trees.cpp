// Tree generation + meshing, single-threaded. Weber–Penn (issue 3 targets: Quaking Aspen ≤ 60 ms,
// Weeping Willow ≤ 300 ms; Arbaro needs ~590 ms and ~2,580 ms); the aspen grammar and the ABOP
// L-systems (issue 12: the grammar aspen at least as fast as the Weber–Penn aspen).

#include "geometry/trees/tree_mesher.h"
#include "scenes/species.h"
#include "scenes/species/treemaker_file.h"

#include <benchmark/benchmark.h>

#include <filesystem>

namespace {

// The species files next to this source (CMake passes sources by absolute path).
const std::filesystem::path kTreeSpeciesDir =
    std::filesystem::path(__FILE__).parent_path().parent_path() / "data" / "species";

void bench_species(benchmark::State& state, const char* file) {
  const sylva::Species species = sylva::load_species(kTreeSpeciesDir / file);
  uint64_t seed = 1;
  size_t triangles = 0, leaves = 0;
  for (auto _ : state) {
    const sylva::TreeMesh mesh = sylva::make_species_mesh(species, seed);
    triangles = mesh.stems.triangles.size();
    leaves = mesh.leaves.size();
    benchmark::DoNotOptimize(mesh.stems.positions.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["leaves"] = static_cast<double>(leaves);
}

void BM_QuakingAspen(benchmark::State& state) { bench_species(state, "quaking_aspen.toml"); }
void BM_BlackTupelo(benchmark::State& state) { bench_species(state, "black_tupelo.toml"); }
void BM_WeepingWillow(benchmark::State& state) { bench_species(state, "weeping_willow.toml"); }
void BM_CaliforniaBlackOak(benchmark::State& state) { bench_species(state, "california_black_oak.toml"); }

void BM_GrammarAspen(benchmark::State& state) { bench_species(state, "quaking_aspen.grammar"); }
void BM_AbopBush(benchmark::State& state) { bench_species(state, "abop_bush.lsys"); }
void BM_AbopStochastic(benchmark::State& state) { bench_species(state, "abop_stochastic.lsys"); }
void BM_AbopMonopodial(benchmark::State& state) { bench_species(state, "abop_monopodial.lsys"); }

void bench_generate_only(benchmark::State& state, const char* file) {
  const sylva::Species species = sylva::load_species(kTreeSpeciesDir / file);
  for (auto _ : state) {
    const sylva::TreeModel model = sylva::make_species_model(species, 1);
    benchmark::DoNotOptimize(model.sections.positions.data());
  }
}

// TREE-MAKER (Neighbors & Hodges §II): the paper's dogwood, growth and meshing, and growth alone.
void BM_DogwoodTemplate(benchmark::State& state) {
  const sylva::TreeMakerTemplate t = sylva::load_treemaker_template(kTreeSpeciesDir / "dogwood.tmpl");
  size_t triangles = 0, leaves = 0;
  for (auto _ : state) {
    const sylva::TreeMesh mesh = sylva::make_tree_mesh(sylva::make_treemaker_tree(t, 1));
    triangles = mesh.stems.triangles.size();
    leaves = mesh.leaves.size();
    benchmark::DoNotOptimize(mesh.stems.positions.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["leaves"] = static_cast<double>(leaves);
}

void BM_DogwoodTemplateGenerateOnly(benchmark::State& state) {
  const sylva::TreeMakerTemplate t = sylva::load_treemaker_template(kTreeSpeciesDir / "dogwood.tmpl");
  for (auto _ : state) {
    const sylva::TreeModel model = sylva::make_treemaker_tree(t, 1);
    benchmark::DoNotOptimize(model.sections.positions.data());
  }
}

void BM_WeepingWillowGenerateOnly(benchmark::State& state) { bench_generate_only(state, "weeping_willow.toml"); }
void BM_QuakingAspenGenerateOnly(benchmark::State& state) { bench_generate_only(state, "quaking_aspen.toml"); }
void BM_GrammarAspenGenerateOnly(benchmark::State& state) { bench_generate_only(state, "quaking_aspen.grammar"); }

}  // namespace

BENCHMARK(BM_QuakingAspen)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BlackTupelo)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WeepingWillow)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaliforniaBlackOak)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WeepingWillowGenerateOnly)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DogwoodTemplate)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DogwoodTemplateGenerateOnly)->Unit(benchmark::kMillisecond);

BENCHMARK(BM_GrammarAspen)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AbopBush)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AbopStochastic)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AbopMonopodial)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_QuakingAspenGenerateOnly)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GrammarAspenGenerateOnly)->Unit(benchmark::kMillisecond);

// Intersection throughput of a Fournier–Grindal crown (issue 13): the half-space solid as
// Embree user geometry against the same crown polygonised (geometry/solids/solid_mesh.h, marching
// tetrahedra of the displaced distance field) and intersected as a triangle mesh. Random rays
// through the crown's bounds, single-threaded; counters report rays per second. `RoundExact` is the
// undisplaced polytope (plane clipping only) against its exact faces as triangles.

#include "core/rng.h"
#include "geometry/solids/solid_mesh.h"
#include "render/embree_scene.h"
#include "scenes/species.h"

#include <benchmark/benchmark.h>

#include <filesystem>

namespace {

const std::filesystem::path kSpeciesDir =
    std::filesystem::path(__FILE__).parent_path().parent_path() / "data" / "species";

// The species' crown; `exact` drops the fBm displacement (the bare §2 polytope).
sylva::HalfSpaceSolid crown_of(const char* file, bool exact) {
  sylva::Species s = sylva::load_species(kSpeciesDir / file);
  if (exact) std::get<sylva::FournierGrindalParams>(s.model).displacement_m = 0.0f;
  const sylva::TreeModel m = sylva::make_species_model(s, 1);
  return m.solids.at(1);
}

void bench_crown(benchmark::State& state, const char* file, bool triangles, bool exact = false) {
  const sylva::HalfSpaceSolid crown = crown_of(file, exact);
  sylva::Scene scene;
  sylva::Prototype p;
  if (triangles) {
    p.triangles = sylva::solid_surface_mesh(crown);
  } else {
    p.solids = {crown};
    p.solid_palettes = {{0u}};
  }
  scene.add_prototype(std::move(p));
  scene.instances.push_back({0, sylva::Mat4(1.0f), 0});
  const sylva::EmbreeScene embree(scene);
  const sylva::Vec3 centre = 0.5f * (crown.bounds.lo + crown.bounds.hi);
  const float radius = glm::length(crown.bounds.hi - crown.bounds.lo);
  sylva::Pcg32 rng(1);
  size_t rays = 0, hits = 0;
  for (auto _ : state) {
    const sylva::Vec3 dir = glm::normalize(sylva::Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()) + 1e-6f);
    const sylva::Vec3 aim = centre + 0.4f * radius * sylva::Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric());
    sylva::RayHit hit;
    hits += embree.intersect(sylva::Ray{aim - 2.0f * radius * dir, dir}, &hit) ? 1 : 0;
    ++rays;
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = static_cast<double>(hits) / static_cast<double>(std::max<size_t>(rays, 1));
  state.counters["triangles"] = static_cast<double>(embree.stats().triangles);
}

void BM_CrownUserGeometry_Round(benchmark::State& state) { bench_crown(state, "fg_round.toml", false); }
void BM_CrownTriangles_Round(benchmark::State& state) { bench_crown(state, "fg_round.toml", true); }
void BM_CrownUserGeometry_RoundExact(benchmark::State& state) { bench_crown(state, "fg_round.toml", false, true); }
void BM_CrownTriangles_RoundExact(benchmark::State& state) { bench_crown(state, "fg_round.toml", true, true); }
void BM_CrownUserGeometry_Poplar(benchmark::State& state) { bench_crown(state, "fg_poplar.toml", false); }
void BM_CrownTriangles_Poplar(benchmark::State& state) { bench_crown(state, "fg_poplar.toml", true); }

}  // namespace

BENCHMARK(BM_CrownUserGeometry_Round);
BENCHMARK(BM_CrownTriangles_Round);
BENCHMARK(BM_CrownUserGeometry_RoundExact);
BENCHMARK(BM_CrownTriangles_RoundExact);
BENCHMARK(BM_CrownUserGeometry_Poplar);
BENCHMARK(BM_CrownTriangles_Poplar);

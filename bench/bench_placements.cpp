// Reading placement lists (scenes/placement_list.h): a CSV of N rows streamed row by row.
// Target (issue 9): 10^6 rows in at most 2 s. And the cost per ray of the instance level: the
// built-in default forest rendered through native Embree instances and through the instance array
// (Scene::instance_level; bench/README.md "Placed trees at scale").

#include "bench/bench_support.h"
#include "render/renderer.h"
#include "scenes/placement_list.h"
#include "scenes/scene_file.h"

#include <benchmark/benchmark.h>
#include <fmt/core.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace sylva {
namespace {

std::filesystem::path write_list(int64_t rows) {
  const auto path = std::filesystem::temp_directory_path() / fmt::format("sylva_bench_list_{}.csv", rows);
  std::ofstream out(path);
  out << "x,y,species,seed,scale,heading\n";
  for (int64_t i = 0; i < rows; ++i)
    out << fmt::format("{:.2f},{:.2f},{},{},{:.3f},{:.1f}\n", static_cast<double>(i % 1000) * 6.0 - 3000.0,
                       static_cast<double>(i / 1000) * 6.0 - 3000.0, i % 2 ? "aspen" : "oak", 1 + i % 5,
                       0.8 + 0.0004 * static_cast<double>(i % 1000), static_cast<double>((i * 37) % 360));
  return path;
}

void bm_placement_list_read(benchmark::State& state) {
  const auto path = write_list(state.range(0));
  for (auto _ : state) {
    double sum = 0;
    for_each_placement_row(path, 1e7f, [&](const PlacementRow& r, int) { sum += r.x + r.scale; });
    benchmark::DoNotOptimize(sum);
  }
  state.counters["rows_per_s"] =
      benchmark::Counter(static_cast<double>(state.range(0)) * state.iterations(), benchmark::Counter::kIsRate);
  std::filesystem::remove(path);
}
BENCHMARK(bm_placement_list_read)->Arg(1000000)->Unit(benchmark::kMillisecond);

// One 1-spp pass over a 320x180 film of the default forest (3 450 instances of 46 prototypes), one
// thread, with the instance level forced; the same samples on both paths.
void bm_render_instance_level(benchmark::State& state, InstanceLevel level) {
  static const SceneFile file = default_scene();
  Scene scene = file.scene;
  scene.instance_level = level;
  const EmbreeScene embree(scene);
  time_render_passes(state, scene, embree, bench_settings(file, 1));
}
BENCHMARK_CAPTURE(bm_render_instance_level, native, InstanceLevel::native)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->MinTime(2.0);
BENCHMARK_CAPTURE(bm_render_instance_level, array, InstanceLevel::array)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->MinTime(2.0);

}  // namespace
}  // namespace sylva

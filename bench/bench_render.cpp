// Rendering throughput: path samples per second and rays (closest-hit + shadow) per second on the
// built-in default scene and on bench/scenes/dense_grove.toml, single-threaded and on all hardware
// threads, plus the BVH build time. Every case renders a fresh film at a fixed resolution, spp and
// seed, so the work per iteration is identical from run to run (see bench/README.md).

#include "bench/bench_support.h"
#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>

namespace sylva {
namespace {

enum class BenchScene { kDefault, kDenseGrove };

// Loaded once: the parse (and the leaf-cloud generation) is not what is measured.
const SceneFile& bench_scene(BenchScene which) {
  static const SceneFile default_file = default_scene();
  static const SceneFile dense_file = load_scene_file(SYLVA_BENCH_SCENES_DIR "/dense_grove.toml");
  return which == BenchScene::kDefault ? default_file : dense_file;
}

// One iteration = one 1-spp pass over a 320×180 film. Timed with the renderer's own clock
// (RenderStats::seconds: the tile loop only, not film allocation).
void bm_render(benchmark::State& state, BenchScene which, int threads) {
  const SceneFile& file = bench_scene(which);
  const EmbreeScene embree(file.scene);
  time_render_passes(state, file.scene, embree, bench_settings(file, threads));
}

// Embree BVH build of every prototype plus the instance-level scene (built once per scene and
// shared by every pass), on all threads.
void bm_build_bvh(benchmark::State& state, BenchScene which) {
  const SceneFile& file = bench_scene(which);
  double build_ms = 0;
  size_t bvh_bytes = 0;
  for (auto _ : state) {
    const EmbreeScene embree(file.scene);
    build_ms += embree.stats().build_ms;
    bvh_bytes = embree.stats().bvh_bytes;
  }
  state.counters["build_ms"] = build_ms / static_cast<double>(state.iterations());
  state.counters["bvh_MiB"] = static_cast<double>(bvh_bytes) / 1048576.0;
}

}  // namespace

BENCHMARK_CAPTURE(bm_build_bvh, default, BenchScene::kDefault)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(bm_build_bvh, dense_grove, BenchScene::kDenseGrove)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_CAPTURE(bm_render, default_1thread, BenchScene::kDefault, 1)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->MinTime(2.0);
BENCHMARK_CAPTURE(bm_render, default_all_threads, BenchScene::kDefault, 0)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->MinTime(2.0);
BENCHMARK_CAPTURE(bm_render, dense_grove_1thread, BenchScene::kDenseGrove, 1)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->MinTime(2.0);
BENCHMARK_CAPTURE(bm_render, dense_grove_all_threads, BenchScene::kDenseGrove, 0)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->MinTime(2.0);

}  // namespace sylva

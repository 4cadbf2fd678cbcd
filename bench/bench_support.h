#pragma once
// What the render benchmarks share: the fixed settings of one timed pass, and the timed loop.

#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>

namespace sylva {

// The scene file's settings (bands, depth) at the benchmarks' fixed resolution, spp and seed.
inline RenderSettings bench_settings(const SceneFile& file, int threads) {
  RenderSettings s = render_settings(file);
  s.width = 320;
  s.height = 180;
  s.spp = 1;
  s.seed = 1;
  s.threads = threads;
  s.progress = false;
  return s;
}

// One iteration = one pass over a fresh film, timed with the renderer's own clock
// (RenderStats::seconds: the tile loop only, not film allocation); counters samples/s, rays/s and
// rays/sample.
inline void time_render_passes(benchmark::State& state, const Scene& scene, const EmbreeScene& embree,
                               const RenderSettings& settings) {
  Renderer renderer(scene, embree, settings);
  uint64_t samples = 0, rays = 0;
  for (auto _ : state) {
    Film film = renderer.make_film();
    const RenderStats stats = renderer.render(film);
    state.SetIterationTime(stats.seconds);
    samples += stats.samples;
    rays += stats.rays;
    benchmark::DoNotOptimize(film);
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(samples), benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
  state.counters["rays/sample"] = static_cast<double>(rays) / static_cast<double>(std::max<uint64_t>(samples, 1));
}

}  // namespace sylva

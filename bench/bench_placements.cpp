// Reading placement lists (scenes/placement_list.h): a CSV of N rows streamed row by row.
// Target (issue 9): 10^6 rows in at most 2 s.

#include "scenes/placement_list.h"

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

}  // namespace
}  // namespace sylva

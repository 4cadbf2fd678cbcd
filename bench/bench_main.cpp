// sylva_bench's entry point: Google Benchmark's, after asking for the renderer's memory pages
// (core/memory.h), so the figures are those of `sylva render`.

#include "core/memory.h"

#include <benchmark/benchmark.h>

int main(int argc, char** argv) {
  sylva::use_huge_pages(argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

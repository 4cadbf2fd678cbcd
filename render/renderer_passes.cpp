// Renderer::render: the tiles of a region rendered in parallel, in passes of growing sample counts
// (progressive and adaptive renders) or one pass; and adaptive sampling's per-pixel decisions
// (docs/sampling.md, "Adaptive sampling").

#include "core/error.h"
#include "core/progress.h"
#include "render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fmt/core.h>

#include <chrono>
#include <cmath>

#include <sys/resource.h>

namespace sylva {

namespace {

// User + system processor time of the whole process so far.
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(u.ru_utime) + seconds(u.ru_stime);
}

// The passes' sample counts, ending at `end`: doubling from `first` (progressive), or `end` alone.
std::vector<uint32_t> pass_levels(uint32_t first, uint32_t end, bool progressive) {
  std::vector<uint32_t> levels;
  if (progressive)
    for (uint32_t l = std::max(first, 1u); l < end; l *= 2) levels.push_back(l);
  levels.push_back(end);
  return levels;
}

// Samples per pixel the first pass of a progressive render without adaptive sampling reaches: a
// pixel's first batch of paths (Renderer::render_pixel) traced together.
constexpr uint32_t kFirstPassSpp = 8;

}  // namespace

uint32_t Renderer::stream0_count(const Film& film, int x, int y) const {
  return static_cast<uint32_t>(film.sum(x, y, adaptive_base_));
}

uint32_t Renderer::stream_target(const Film& film, int x, int y, int stream) const {
  // The other stream's pilot: its first m samples of each noise channel (sums over the pilot of
  // stream 0, and of both streams, in the film).
  const auto m = static_cast<uint32_t>(settings_.pilot_spp / 2);
  const auto most = static_cast<uint32_t>((settings_.spp + 1 - stream) / 2);
  const double t2 = sqr(static_cast<double>(settings_.noise_threshold));
  double need = m;
  for (size_t k = 0; k < noise_channels_.size(); ++k) {
    const int pilot0 = adaptive_base_ + 1 + 2 * static_cast<int>(k), pilot_all = pilot0 + 1;
    double sum = film.sum(x, y, pilot0), sum_sq = film.sum_sq(x, y, pilot0);
    if (stream == 0) {  // stream 1's pilot decides
      sum = film.sum(x, y, pilot_all) - sum;
      sum_sq = film.sum_sq(x, y, pilot_all) - sum_sq;
    }
    const double mean = sum / m;
    const double variance = std::max(0.0, (sum_sq - m * mean * mean) / (m - 1));
    // The estimator (mean₀ + mean₁)/2 with n samples in each stream has variance σ²/(2n): n ≥
    // σ²/(2 T² (μ² + floor)) reaches the relative error T.
    need = std::max(need, variance / (2.0 * t2 * (mean * mean + noise_floor_[k])));
  }
  return static_cast<uint32_t>(std::clamp(std::ceil(need), static_cast<double>(m), static_cast<double>(most)));
}

double Renderer::channel_mean(const Film& film, int x, int y, int c) const {
  if (!adaptive()) return film.mean(x, y, c);
  const double n = film.count(x, y), n0 = stream0_count(film, x, y), n1 = n - n0;
  if (n0 == 0 || n1 == 0) return film.mean(x, y, c);
  const double even = film.sum(x, y, even_channel(static_cast<size_t>(c)));
  return 0.5 * (even / n0 + (film.sum(x, y, c) - even) / n1);
}

double Renderer::channel_variance_of_mean(const Film& film, int x, int y, int c) const {
  if (!adaptive()) return film.variance_of_mean(x, y, c);
  const double n = film.count(x, y), n0 = stream0_count(film, x, y), n1 = n - n0;
  if (n0 < 2 || n1 < 2) return film.variance_of_mean(x, y, c);
  const int e = even_channel(static_cast<size_t>(c));
  const double s0 = film.sum(x, y, e), q0 = film.sum_sq(x, y, e);
  const double s1 = film.sum(x, y, c) - s0, q1 = film.sum_sq(x, y, c) - q0;
  const double v0 = std::max(0.0, (q0 - s0 * s0 / n0) / (n0 - 1)) / n0;
  const double v1 = std::max(0.0, (q1 - s1 * s1 / n1) / (n1 - 1)) / n1;
  return 0.25 * (v0 + v1);
}

RenderStats Renderer::render(Film& film, const PixelRegion& region, SampleRange samples) {
  check_film(film);
  if (!film.window().contains(region))
    throw Error(fmt::format("region [{}, {}) x [{}, {}) is not inside the film's window", region.x0, region.x1,
                            region.y0, region.y1));
  const auto spp = static_cast<uint32_t>(settings_.spp);
  if (adaptive() && (samples.first != 0 || film.first_sample() != 0 || samples.end != spp))
    throw Error(
        "adaptive sampling decides each pixel's samples from all of them: split the render by tiles, not by samples");
  RenderStats stats;
  stats.embree = embree_.stats();
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  const uint32_t target = samples.end;
  // A pixel's next sample index (one sequence); it renders [next, target).
  const auto next_sample = [&](int x, int y) { return film.first_sample() + film.count(x, y); };
  uint64_t remaining = 0;
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const uint32_t next = next_sample(x, y);
      if (!adaptive() && next < samples.first)
        throw Error(fmt::format("pixel ({}, {}) has samples up to {}, so samples from {} on cannot follow in order", x,
                                y, next, samples.first));
      remaining += target - std::min(target, next);
    }
  if (region.empty()) return stats;

  // Adaptive: pass levels count each stream's samples (the pilot's half, doubling, to spp's half).
  const std::vector<uint32_t> levels =
      adaptive() ? pass_levels(static_cast<uint32_t>(settings_.pilot_spp / 2), (spp + 1) / 2, true)
                 : pass_levels(std::max(samples.first + 1, kFirstPassSpp), target, progressive());
  Progress progress("render", remaining, settings_.progress, "samples", settings_.on_progress);
  tbb::enumerable_thread_specific<uint64_t> rays(0), samples_added(0);
  std::atomic<bool> stopped{false};
  // One pixel's part of pass `pass`: the samples it adds and, adaptive, the samples it will never
  // take (counted as done by the progress).
  const auto render_pass_pixel = [&](int x, int y, size_t pass, uint64_t& pixel_rays, uint64_t& skipped) {
    if (!adaptive()) {
      const uint32_t next = next_sample(x, y), end = std::min(target, levels[pass]);
      if (next >= end) return uint64_t{0};
      render_pixel(film, x, y, kAllSamples, next, end, pixel_rays);
      return uint64_t{end - next};
    }
    uint64_t added = 0;
    for (int s = 0; s < 2; ++s) {
      const uint32_t n0 = stream0_count(film, x, y);
      const uint32_t have = s == 0 ? n0 : film.count(x, y) - n0;
      // Every pixel's pilot is complete before the first decision (the first pass is the pilot).
      const uint32_t want = pass == 0 ? levels[0] : stream_target(film, x, y, s);
      const uint32_t end = std::min(want, levels[pass]);
      if (have < end) render_pixel(film, x, y, s, have, end, pixel_rays);
      added += end - std::min(have, end);
      // The samples the stream will never take, counted once per run: in the first deciding pass
      // whose level reaches its target.
      const uint32_t most = (spp + 1 - static_cast<uint32_t>(s)) / 2;
      if (pass > 0 && end == want && (pass == 1 || levels[pass - 1] < want)) skipped += most - want;
    }
    return added;
  };
  const int ts = settings_.tile_size;
  const int tiles_x = (region.width() + ts - 1) / ts, tiles_y = (region.height() + ts - 1) / ts;
  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  for (size_t pass = 0; pass < levels.size() && !stopped; ++pass) {
    arena.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<int>(0, tiles_x * tiles_y, 1),
          [&](const tbb::blocked_range<int>& range) {
            for (int tile = range.begin(); tile != range.end(); ++tile) {
              const int x0 = region.x0 + (tile % tiles_x) * ts, y0 = region.y0 + (tile / tiles_x) * ts;
              const int x1 = std::min(x0 + ts, region.x1), y1 = std::min(y0 + ts, region.y1);
              uint64_t& tile_rays = rays.local();
              uint64_t added = 0, skipped = 0;
              for (int y = y0; y < y1 && !stopped; ++y)
                for (int x = x0; x < x1; ++x) {
                  // Stop between pixels; each pixel keeps whole samples, in order.
                  if (settings_.cancel && settings_.cancel->load(std::memory_order_relaxed)) {
                    stopped = true;
                    break;
                  }
                  added += render_pass_pixel(x, y, pass, tile_rays, skipped);
                }
              samples_added.local() += added;
              progress.add(added + skipped);
              if (stopped) return;
            }
          },
          tbb::simple_partitioner());
    });
  }
  progress.finish();
  stats.interrupted = stopped.load();
  stats.rays = rays.combine(std::plus<>());
  stats.samples = samples_added.combine(std::plus<>());
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats.cpu_seconds = process_cpu_seconds() - cpu_start;
  return stats;
}

}  // namespace sylva

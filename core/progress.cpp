#include "core/progress.h"

#include <unistd.h>

#include <fmt/core.h>

#include <cstdio>

namespace sylva {

namespace {
std::string format_duration(double s) {
  if (!(s >= 0) || s > 1e7) return "--:--";
  const auto t = static_cast<long>(s + 0.5);
  return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, (t / 60) % 60, t % 60)
                   : fmt::format("{:02}:{:02}", t / 60, t % 60);
}
std::string format_rate(double r) {
  if (r >= 1e6) return fmt::format("{:.2f} M", r / 1e6);
  if (r >= 1e3) return fmt::format("{:.1f} k", r / 1e3);
  return fmt::format("{:.0f} ", r);
}
}  // namespace

bool Progress::terminal_stderr() { return ::isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::string label, uint64_t total, bool enabled, std::string unit, ProgressSink sink)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(enabled && terminal_stderr()),
      sink_(std::move(sink)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() { finish(); }

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::add(uint64_t n) {
  done_.fetch_add(n, std::memory_order_relaxed);
  if (!enabled_ && !sink_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(250)) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || now - last_draw_ < std::chrono::milliseconds(250)) return;
  last_draw_ = now;
  if (sink_) sink_(report());
  if (enabled_) draw(false);
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (sink_) sink_(report());
  if (enabled_) draw(true);
}

ProgressReport Progress::report() const {
  ProgressReport r;
  r.label = label_;
  r.done = std::min(done_.load(), total_);
  r.total = total_;
  r.elapsed_s = elapsed_seconds();
  const double rate = r.elapsed_s > 0 ? static_cast<double>(r.done) / r.elapsed_s : 0.0;
  r.remaining_s = rate > 0 ? static_cast<double>(r.total - r.done) / rate : -1.0;
  return r;
}

void Progress::draw(bool final) {
  const ProgressReport r = report();
  const uint64_t done = r.done;
  const double f = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  const double elapsed = r.elapsed_s;
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double remaining = r.remaining_s;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(f * kWidth);
  fmt::print(stderr, "\r{} [{}{}] {:5.1f}%  {} elapsed  {} left  {}{}/s\x1b[K{}", label_, std::string(filled, '#'),
             std::string(kWidth - filled, '.'), 100.0 * f, format_duration(elapsed), format_duration(remaining),
             format_rate(rate), unit_, final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace sylva

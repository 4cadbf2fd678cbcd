#include "core/progress.h"

#include <unistd.h>

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
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
double fraction(uint64_t done, uint64_t total) {
  return total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
}
double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
constexpr double kCheckInterval_s = 0.25;  // how often add() looks at the clock's verdict
}  // namespace

bool progress_line_due(const ProgressCadence& cadence, bool first, double since_line_s, double step) {
  if (first) return since_line_s >= cadence.first_s;
  if (since_line_s >= cadence.max_interval_s) return true;
  return since_line_s >= cadence.min_interval_s && step >= cadence.min_step;
}

std::string progress_line(const ProgressReport& r, std::string_view unit, bool final) {
  const double rate = r.elapsed_s > 0 ? static_cast<double>(r.done) / r.elapsed_s : 0.0;
  return fmt::format("{}: {:.1f}% {}/{} {}, {} elapsed, {}{}/s, {}", r.label, 100.0 * fraction(r.done, r.total), r.done,
                     r.total, unit, format_duration(r.elapsed_s), format_rate(rate), unit,
                     final && r.done >= r.total ? "done" : format_duration(r.remaining_s) + " left");
}

bool Progress::terminal_stderr() { return ::isatty(STDERR_FILENO) == 1; }

ProgressOutput stderr_progress(bool enabled) {
  ProgressOutput out;
  out.style = !enabled ? ProgressStyle::none : Progress::terminal_stderr() ? ProgressStyle::bar : ProgressStyle::lines;
  return out;
}

Progress::Progress(std::string label, uint64_t total, bool enabled, std::string unit, ProgressSink sink)
    : Progress(std::move(label), total, stderr_progress(enabled), std::move(unit), std::move(sink)) {}

Progress::Progress(std::string label, uint64_t total, ProgressOutput output, std::string unit, ProgressSink sink)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      output_(std::move(output)),
      sink_(std::move(sink)) {
  if (!output_.clock_s) output_.clock_s = steady_seconds;
  if (!output_.write)
    output_.write = [](std::string_view text) {
      std::fwrite(text.data(), 1, text.size(), stderr);
      std::fflush(stderr);
    };
  start_s_ = output_.clock_s();
  last_check_s_ = start_s_;
  line_s_ = start_s_;
}

Progress::~Progress() { finish(); }

double Progress::now_s() const { return output_.clock_s(); }

double Progress::elapsed_seconds() const { return now_s() - start_s_; }

void Progress::add(uint64_t n) {
  done_.fetch_add(n, std::memory_order_relaxed);
  if (output_.style == ProgressStyle::none && !sink_) return;
  const double now = now_s();
  if (now - last_check_s_.load(std::memory_order_relaxed) < kCheckInterval_s) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || finished_ || now - last_check_s_.load() < kCheckInterval_s) return;
  last_check_s_ = now;
  if (sink_) sink_(report());
  print(false);
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (sink_) sink_(report());
  print(true);
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

// Under the mutex.
void Progress::print(bool final) {
  if (output_.style == ProgressStyle::bar) {
    draw_bar(report(), final);
    return;
  }
  if (output_.style != ProgressStyle::lines) return;
  const ProgressReport r = report();
  const double now = start_s_ + r.elapsed_s;
  // The last line is finish()'s, so a render that ends between two checks does not log 100 % twice.
  const bool due = final ? lines_ > 0
                         : r.done < total_ && progress_line_due(output_.cadence, lines_ == 0, now - line_s_,
                                                                fraction(r.done - line_done_, total_));
  if (!due) return;
  output_.write(progress_line(r, unit_, final) + "\n");
  line_s_ = now;
  line_done_ = r.done;
  ++lines_;
}

void Progress::draw_bar(const ProgressReport& r, bool final) {
  const double f = fraction(r.done, total_);
  const double rate = r.elapsed_s > 0 ? static_cast<double>(r.done) / r.elapsed_s : 0.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(f * kWidth);
  output_.write(fmt::format("\r{} [{}{}] {:5.1f}%  {} elapsed  {} left  {}{}/s\x1b[K{}", label_,
                            std::string(filled, '#'), std::string(kWidth - filled, '.'), 100.0 * f,
                            format_duration(r.elapsed_s), format_duration(r.remaining_s), format_rate(rate), unit_,
                            final ? "\n" : ""));
}

}  // namespace sylva

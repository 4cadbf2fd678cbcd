#pragma once
// A progress bar on stderr: percent, elapsed, remaining, and a rate. Silent when stderr is not a
// terminal or when disabled. Thread-safe: workers call add(); printing is rate-limited. A sink, if
// given, receives the same figures (every 250 ms and at the end) whether or not a bar is drawn: the
// render call's observer (pipeline/render_call.h).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>

namespace sylva {

// What a sink is told: work done of the total, and the time taken and (once a rate is known) left.
struct ProgressReport {
  std::string_view label;
  uint64_t done = 0;
  uint64_t total = 0;
  double elapsed_s = 0;
  double remaining_s = -1;  // negative until a rate is known
};
using ProgressSink = std::function<void(const ProgressReport&)>;

class Progress {
 public:
  Progress(std::string label, uint64_t total, bool enabled, std::string unit = "samples", ProgressSink sink = {});
  ~Progress();
  void add(uint64_t n);
  void finish();
  double elapsed_seconds() const;
  // Whether a bar would be drawn (stderr is a terminal and enabled).
  static bool terminal_stderr();

 private:
  void draw(bool final);
  ProgressReport report() const;

  std::string label_, unit_;
  uint64_t total_;
  bool enabled_;
  ProgressSink sink_;
  std::atomic<uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex mutex_;
  bool finished_ = false;
};

}  // namespace sylva

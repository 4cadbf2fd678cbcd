#pragma once
// A progress bar on stderr: percent, elapsed, remaining, and a rate. Silent when stderr is not a
// terminal or when disabled. Thread-safe: workers call add(); printing is rate-limited.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace sylva {

class Progress {
 public:
  Progress(std::string label, uint64_t total, bool enabled, std::string unit = "samples");
  ~Progress();
  void add(uint64_t n);
  void finish();
  double elapsed_seconds() const;
  // Whether a bar would be drawn (stderr is a terminal and enabled).
  static bool terminal_stderr();

 private:
  void draw(bool final);

  std::string label_, unit_;
  uint64_t total_;
  bool enabled_;
  std::atomic<uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex mutex_;
  bool finished_ = false;
};

}  // namespace sylva

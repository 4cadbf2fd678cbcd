#pragma once
// Progress on stderr: percent, work done of the total, elapsed, rate and time left. On a terminal a
// bar redrawn in place; otherwise (a log file, a Slurm job's output) one plain line now and then
// (ProgressCadence), each flushed, so `tail -f` and `grep` show the ETA long before the end; nothing
// when disabled (--quiet). Thread-safe: workers call add(); printing is rate-limited. A sink, if
// given, receives the same figures (every 250 ms and at the end) whether or not anything is
// printed: the render call's observer (pipeline/render_call.h).

#include <atomic>
#include <chrono>  // kept for the files that use it through render/renderer.h
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

// How progress is printed: not at all, a bar redrawn in place (a terminal), or lines (a log).
enum class ProgressStyle { none, bar, lines };

// When ProgressStyle::lines prints: the first line once `first_s` have passed (the render has
// started, and its ETA); after it, a line when `min_interval_s` have passed and `min_step` of the
// total is done since the previous line, or when `max_interval_s` have passed whatever was done;
// and a last line at the end if any line was printed (a render shorter than `first_s` prints
// none). So a 2-minute render logs about 10 lines and a 10-hour one a line every 5 minutes. The
// decision is taken when work is added (the renderer adds a tile at a time).
struct ProgressCadence {
  double first_s = 10;
  double min_interval_s = 10;
  double min_step = 0.1;  // fraction of the total
  double max_interval_s = 300;
};

// Whether a line is due: `since_line_s` seconds and `step` (fraction of the total) since the
// previous line, or since the start when `first`.
bool progress_line_due(const ProgressCadence& cadence, bool first, double since_line_s, double step);

// "render: 42.0% 1234567/2939520 samples, 00:35 elapsed, 35.3 ksamples/s, 00:48 left" ("done" in
// place of the time left on the last line of finished work). No timestamp, no control characters.
std::string progress_line(const ProgressReport& report, std::string_view unit, bool final);

// Where and how a Progress prints; the default is stderr, the style from whether it is a terminal,
// and the steady clock. Tests substitute the clock and the writer.
struct ProgressOutput {
  ProgressStyle style = ProgressStyle::none;
  ProgressCadence cadence;
  std::function<double()> clock_s;              // monotonic seconds; empty: std::chrono::steady_clock
  std::function<void(std::string_view)> write;  // empty: stderr, flushed after every write
};
// The style of an enabled progress: a bar when stderr is a terminal, lines otherwise.
ProgressOutput stderr_progress(bool enabled);

class Progress {
 public:
  // On stderr (stderr_progress(enabled)).
  Progress(std::string label, uint64_t total, bool enabled, std::string unit = "samples", ProgressSink sink = {});
  Progress(std::string label, uint64_t total, ProgressOutput output, std::string unit = "samples",
           ProgressSink sink = {});
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void add(uint64_t n);
  void finish();
  double elapsed_seconds() const;
  // Whether stderr is a terminal (a bar is drawn there; lines are printed otherwise).
  static bool terminal_stderr();

 private:
  double now_s() const;
  void print(bool final);
  void draw_bar(const ProgressReport& r, bool final);
  ProgressReport report() const;

  std::string label_, unit_;
  uint64_t total_;
  ProgressOutput output_;
  ProgressSink sink_;
  std::atomic<uint64_t> done_{0};
  double start_s_ = 0;
  std::atomic<double> last_check_s_{0};
  std::mutex mutex_;
  bool finished_ = false;
  // Lines: when the previous line was printed and how much was done then; lines printed so far.
  double line_s_ = 0;
  uint64_t line_done_ = 0;
  int lines_ = 0;
};

}  // namespace sylva

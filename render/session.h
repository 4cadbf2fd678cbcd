#pragma once
// A render session: renders a film to settings.spp in rounds, writing a checkpoint when a round is
// cut short — every `checkpoint_minutes`, and for good when interrupted — and resuming from a
// checkpoint. Because every pixel keeps whole samples in order (render/film.h), a resumed render is
// bit-identical to an uninterrupted one. Also here: the process's SIGINT/SIGTERM handling, so the
// command line only parses arguments and calls the library.

#include "render/embree_scene.h"
#include "render/film.h"
#include "render/renderer.h"
#include "render/scene.h"

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace sylva {

// While one is alive, SIGINT and SIGTERM are handled in one of two ways (OnSignal):
//  - set_flag: set a process-wide flag instead of ending the process (a render stops cleanly and
//    checkpoints), and a second signal ends it at once (the default action is restored by the first);
//  - exit: end the process at once with status 128 + signal, after a message on stderr. For work
//    that writes nothing and cannot poll a flag (loading a scene, building the BVH).
// Construction clears the flag; destruction restores the default actions. Signal handling is
// process-wide state: keep at most one alive, owned by the program's entry point (the CLI).
class InterruptHandlers {
 public:
  enum class OnSignal { set_flag, exit };
  explicit InterruptHandlers(OnSignal on_signal = OnSignal::set_flag);
  // Switches how the next signal is handled (e.g. to set_flag once the render starts).
  static void set(OnSignal on_signal);
  ~InterruptHandlers();
  InterruptHandlers(const InterruptHandlers&) = delete;
  InterruptHandlers& operator=(const InterruptHandlers&) = delete;

  // Set once a signal arrived; pass it as SessionOptions::interrupt.
  static const std::atomic<bool>& flag();
};

// Sets `stop` once `interrupt` (optional) is set or `minutes` (> 0) have passed since construction,
// polling `interrupt` every 50 ms (a signal handler cannot wake a thread). Runs on its own thread,
// which the destructor wakes and joins on every path, exceptions included, so an exception thrown
// while it watches propagates instead of ending the process (std::terminate).
class StopWatcher {
 public:
  StopWatcher(std::atomic<bool>& stop, const std::atomic<bool>* interrupt, double minutes);
  ~StopWatcher();
  StopWatcher(const StopWatcher&) = delete;
  StopWatcher& operator=(const StopWatcher&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

struct SessionOptions {
  std::filesystem::path checkpoint;  // checkpoint file; empty: none is written or resumed
  std::string key;                   // what a checkpoint must match to be resumed (checkpoint_key())
  bool resume = false;               // start from `checkpoint` (sylva::Error if missing or of another render)
  double checkpoint_minutes = 10.0;  // write a checkpoint this often; 0 = only when interrupted
  const std::atomic<bool>* interrupt = nullptr;  // stop for good once set (e.g. InterruptHandlers::flag())
  // Told about a periodic checkpoint that could not be written (the render goes on; the message
  // names the file and the reason). The final checkpoint of an interrupted render throws instead.
  std::function<void(const std::string&)> warn;
};

struct SessionResult {
  Film film;
  RenderStats stats;          // summed over the rounds of this run (seconds: rendering only)
  bool interrupted = false;   // stopped by `interrupt` before the film was complete (checkpointed)
  bool time_limited = false;  // stopped by settings.time_limit_s: the film is the render's result
  int checkpoints = 0;        // checkpoints written
};

// The checkpoint of a render writing `output`: beside it, "<output name>.checkpoint". A name that
// would exceed the file system's 255 bytes keeps its first bytes and ends with a hash of the whole
// name ("<start>-<16 hex digits>.checkpoint"), so every output name accepted has a checkpoint.
std::filesystem::path checkpoint_path_for(const std::filesystem::path& output);

// What a checkpoint of this render must match: everything that changes the samples (Sylva's
// version, the scene's content hash, seed, resolution, depth, band names and sampler).
std::string checkpoint_key(const std::string& scene_hash, const RenderSettings& settings);

class RenderSession {
 public:
  // `scene` and `embree` (built from `scene`) must outlive the session. settings.cancel is replaced
  // by the session's own flag; stop a session through options.interrupt. With options.resume the
  // checkpoint is loaded here, so a missing or mismatched one fails before any rendering; so does
  // one that holds more samples per pixel than settings.spp (an image of fewer samples cannot be
  // made from it: render afresh) or a film of another size.
  RenderSession(const Scene& scene, const EmbreeScene& embree, RenderSettings settings, SessionOptions options);
  RenderSession(const RenderSession&) = delete;
  RenderSession& operator=(const RenderSession&) = delete;

  // Samples in the film the session starts from (a resumed checkpoint's; 0 for a fresh film).
  uint64_t resumed_samples() const { return resumed_samples_; }

  // Renders in rounds until every pixel has settings.spp samples (or adaptive sampling's fewer), the
  // interrupt is set or settings.time_limit_s seconds of rendering have passed in this run; writes a
  // checkpoint after every round cut short by the period or the interrupt (if options.checkpoint is
  // set). Hands the film over: call once. Exceptions from rendering or checkpointing propagate.
  SessionResult run();

  // Removes the checkpoint file (call once the outputs are written).
  void remove_checkpoint() const;

  // Saves `film` (this session's, e.g. SessionResult::film) as the checkpoint: before writing the
  // outputs, so a failed or interrupted write loses no samples (`--resume` then only writes).
  void save_checkpoint(const Film& film) const;

  // For make_image() and the channel names.
  const Renderer& renderer() const { return renderer_; }

 private:
  SessionOptions options_;
  std::atomic<bool> stop_{false};
  Renderer renderer_;
  Film film_;
  uint64_t resumed_samples_ = 0;
  bool ran_ = false;
};

}  // namespace sylva

#include "render/session.h"

#include "core/error.h"

#include <fmt/core.h>

#include <chrono>
#include <csignal>

namespace sylva {

namespace {

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void on_interrupt_signal(int sig) {
  g_interrupted.store(true);
  std::signal(sig, SIG_DFL);  // a second signal ends the process at once
}

}  // namespace

InterruptHandlers::InterruptHandlers() {
  g_interrupted = false;
  std::signal(SIGINT, on_interrupt_signal);
  std::signal(SIGTERM, on_interrupt_signal);
}

InterruptHandlers::~InterruptHandlers() {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

const std::atomic<bool>& InterruptHandlers::flag() { return g_interrupted; }

StopWatcher::StopWatcher(std::atomic<bool>& stop, const std::atomic<bool>* interrupt, double minutes) {
  thread_ = std::thread([this, &stop, interrupt, minutes] {
    const auto start = std::chrono::steady_clock::now();
    std::unique_lock lock(mutex_);
    while (!done_) {
      const double elapsed_min = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 60.0;
      if ((interrupt && interrupt->load()) || (minutes > 0 && elapsed_min >= minutes)) {
        stop = true;
        return;
      }
      wake_.wait_for(lock, std::chrono::milliseconds(50));
    }
  });
}

StopWatcher::~StopWatcher() {
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::string checkpoint_key(const std::string& scene_hash, const RenderSettings& settings) {
  std::string key = fmt::format("sylva {} scene {} seed {} res {}x{} depth {} bands", SYLVA_VERSION, scene_hash,
                                settings.seed, settings.width, settings.height, settings.integrator.max_depth);
  for (const Band& b : settings.bands) key += " " + b.name;
  if (settings.quantity != Quantity::radiance) key += fmt::format(" quantity {}", quantity_name(settings.quantity));
  return key;
}

namespace {

RenderSettings with_cancel(RenderSettings settings, const std::atomic<bool>* cancel) {
  settings.cancel = cancel;
  return settings;
}

}  // namespace

RenderSession::RenderSession(const Scene& scene, const EmbreeScene& embree, RenderSettings settings,
                             SessionOptions options)
    : options_(std::move(options)), renderer_(scene, embree, with_cancel(std::move(settings), &stop_)) {
  if (options_.resume) {
    if (options_.checkpoint.empty()) throw Error("resume needs a checkpoint file");
    film_ = Film::load(options_.checkpoint, options_.key);
    resumed_samples_ = film_.total_samples();
  } else {
    film_ = renderer_.make_film();
  }
}

SessionResult RenderSession::run() {
  if (ran_) throw Error("a render session runs once");
  ran_ = true;
  SessionResult result;
  result.stats.embree = renderer_.embree_stats();
  // Periodic checkpoints only make sense with somewhere to write them.
  const double period = options_.checkpoint.empty() ? 0.0 : options_.checkpoint_minutes;
  while (true) {
    stop_ = false;
    RenderStats round;
    {
      const StopWatcher watcher(stop_, options_.interrupt, period);
      round = renderer_.render(film_);
    }
    result.stats.samples += round.samples;
    result.stats.rays += round.rays;
    result.stats.seconds += round.seconds;
    if (!round.interrupted) break;
    if (!options_.checkpoint.empty()) {
      film_.save(options_.checkpoint, options_.key);
      ++result.checkpoints;
    }
    if (options_.interrupt && options_.interrupt->load()) {
      result.interrupted = true;
      break;
    }
  }
  result.stats.interrupted = result.interrupted;
  result.film = std::move(film_);
  return result;
}

void RenderSession::remove_checkpoint() const {
  if (!options_.checkpoint.empty()) std::filesystem::remove(options_.checkpoint);
}

}  // namespace sylva

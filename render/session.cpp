#include "render/session.h"

#include "core/error.h"
#include "core/hash.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <csignal>

#include <unistd.h>

namespace sylva {

namespace {

std::atomic<bool> g_interrupted{false};
std::atomic<bool> g_exit_on_signal{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void on_interrupt_signal(int sig) {
  if (g_exit_on_signal.load()) {
    // Only async-signal-safe calls here.
    constexpr char kMessage[] = "\nsylva: interrupted\n";
    [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
    ::_exit(128 + sig);
  }
  g_interrupted.store(true);
  std::signal(sig, SIG_DFL);  // a second signal ends the process at once
}

}  // namespace

InterruptHandlers::InterruptHandlers(OnSignal on_signal) {
  g_interrupted = false;
  set(on_signal);
  std::signal(SIGINT, on_interrupt_signal);
  std::signal(SIGTERM, on_interrupt_signal);
}

void InterruptHandlers::set(OnSignal on_signal) { g_exit_on_signal = on_signal == OnSignal::exit; }

InterruptHandlers::~InterruptHandlers() {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  g_exit_on_signal = false;
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

std::filesystem::path checkpoint_path_for(const std::filesystem::path& output) {
  constexpr size_t kNameMax = 255;
  constexpr std::string_view kSuffix = ".checkpoint";
  std::string name = output.filename().string() + std::string(kSuffix);
  if (name.size() > kNameMax) {
    const std::string hash = hex64(mix64(fnv1a64(output.filename().string())));
    name = output.filename().string().substr(0, kNameMax - kSuffix.size() - hash.size() - 1) + "-" + hash +
           std::string(kSuffix);
  }
  return output.parent_path() / name;
}

std::string checkpoint_key(const std::string& scene_hash, const RenderSettings& settings) {
  std::string key = fmt::format("sylva {} scene {} seed {} res {}x{} depth {} bands", SYLVA_VERSION, scene_hash,
                                settings.seed, settings.width, settings.height, settings.integrator.max_depth);
  for (const Band& b : settings.bands) key += " " + b.name;
  key += fmt::format(" sampler {}", sampler_name(settings.sampler));
  if (settings.integrator.light_samples != 1)
    key += fmt::format(" light_samples {}", settings.integrator.light_samples);
  if (settings.quantity != Quantity::radiance) key += fmt::format(" quantity {}", quantity_name(settings.quantity));
  if (settings.features) key += " features";
  if (settings.noise_threshold > 0) {
    key += fmt::format(" adaptive {:a} pilot {}", static_cast<double>(settings.noise_threshold), settings.pilot_spp);
    for (const auto& c : settings.noise_channels) key += " " + c;
  }
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
    const RenderSettings& s = renderer_.settings();
    const Film fresh = renderer_.make_film();
    if (film_.width() != s.width || film_.height() != s.height || film_.channels() != fresh.channels() ||
        film_.window() != fresh.window() || film_.first_sample() != 0)
      throw Error(
          fmt::format("{}: the checkpoint's film ({}x{}, {} channels) is not this render's ({}x{}, {} channels)",
                      options_.checkpoint.string(), film_.width(), film_.height(), film_.channels(), s.width, s.height,
                      fresh.channels()));
    uint32_t most = 0;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) most = std::max(most, film_.count(x, y));
    if (most > static_cast<uint32_t>(s.spp))
      throw Error(
          fmt::format("{}: the checkpoint holds up to {} samples per pixel, more than --spp {}; resume with "
                      "--spp {} or more, or render afresh without --resume",
                      options_.checkpoint.string(), most, s.spp, most));
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
  const double limit = renderer_.settings().time_limit_s;
  while (true) {
    // An interrupt that came before the round stops it at once (the watcher polls only every 50 ms).
    stop_ = options_.interrupt && options_.interrupt->load();
    // The round ends at the next checkpoint or at the time limit, whichever comes first.
    const double left = limit > 0 ? limit - result.stats.seconds : 0.0;
    const bool limit_first = limit > 0 && (period <= 0 || left < 60.0 * period);
    RenderStats round;
    {
      const StopWatcher watcher(stop_, options_.interrupt, limit_first ? std::max(left, 1e-3) / 60.0 : period);
      round = renderer_.render(film_);
    }
    result.stats.samples += round.samples;
    result.stats.rays += round.rays;
    result.stats.seconds += round.seconds;
    result.stats.cpu_seconds += round.cpu_seconds;
    if (!round.interrupted) break;
    if (limit_first && !(options_.interrupt && options_.interrupt->load())) {
      result.time_limited = true;
      break;
    }
    const bool interrupted = options_.interrupt && options_.interrupt->load();
    if (!options_.checkpoint.empty()) {
      try {
        film_.save(options_.checkpoint, options_.key);
        ++result.checkpoints;
      } catch (const Error& e) {
        // A periodic checkpoint is insurance: the render goes on. The final one is the only copy.
        if (interrupted || !options_.warn) throw;
        options_.warn(fmt::format("warning: checkpoint not written, rendering goes on: {}", e.what()));
      }
    }
    if (interrupted) {
      result.interrupted = true;
      break;
    }
  }
  result.stats.interrupted = result.interrupted;
  result.film = std::move(film_);
  return result;
}

void RenderSession::save_checkpoint(const Film& film) const {
  if (!options_.checkpoint.empty()) film.save(options_.checkpoint, options_.key);
}

void RenderSession::remove_checkpoint() const {
  if (!options_.checkpoint.empty()) std::filesystem::remove(options_.checkpoint);
}

}  // namespace sylva

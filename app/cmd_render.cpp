// `sylva render`: scene file (or the built-in default) → multi-channel EXR + PNG preview.

#include "app/commands.h"
#include "core/color.h"
#include "core/error.h"
#include "core/image.h"
#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <fmt/core.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <thread>

namespace sylva {

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_signal(int sig) {
  g_interrupted.store(true);
  std::signal(sig, SIG_DFL);  // a second signal ends the process at once
}

struct RenderOptions {
  std::string scene;
  std::string exr;
  std::string png;
  int spp = 0;
  std::string res;
  int threads = 0;
  int64_t seed = -1;
  std::string bands;
  int max_depth = 0;
  bool quiet = false;
  bool resume = false;
  double checkpoint_minutes = 10.0;
  float exposure = 0.0f;
  bool exposure_set = false;
  std::string view;
};

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    const size_t end = s.find(',', start);
    std::string item = s.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!item.empty()) out.push_back(item);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

// Exposure for the preview: the median luminance of the visible band maps to 18% grey.
float auto_exposure_ev(const Image& image, const std::array<std::string, 3>& channels) {
  const int r = image.find_channel(channels[0]), g = image.find_channel(channels[1]),
            b = image.find_channel(channels[2]);
  std::vector<float> lum;
  lum.reserve(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float l = 0.2126f * image.at(x, y, r) + 0.7152f * image.at(x, y, g) + 0.0722f * image.at(x, y, b);
      if (l > 0 && std::isfinite(l)) lum.push_back(l);
    }
  if (lum.empty()) return 0.0f;
  std::nth_element(lum.begin(), lum.begin() + lum.size() / 2, lum.end());
  return std::log2(0.18f / lum[lum.size() / 2]);
}

int run_render(const RenderOptions& opt) {
  // From here on SIGINT/SIGTERM stop the render cleanly (a checkpoint is written).
  g_interrupted = false;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  SceneFile file = opt.scene.empty() ? default_scene() : load_scene_file(opt.scene);
  if (!opt.quiet)
    for (const std::string& w : file.warnings) fmt::print(stderr, "{}\n", w);
  RenderSettings settings = render_settings(file);
  if (!opt.res.empty()) {
    int w = 0, h = 0;
    char extra = 0;
    if (std::sscanf(opt.res.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w <= 0 || h <= 0 || w > 65536 || h > 65536)
      throw Error("--res: expected WIDTHxHEIGHT, e.g. 1280x720, not '" + opt.res + "'");
    settings.width = w;
    settings.height = h;
  }
  if (opt.spp > 0) settings.spp = opt.spp;
  if (opt.seed >= 0) settings.seed = static_cast<uint64_t>(opt.seed);
  settings.threads = opt.threads;
  if (opt.max_depth > 0) settings.integrator.max_depth = opt.max_depth;
  const std::vector<std::string> band_names = opt.bands.empty() ? file.bands : split_list(opt.bands);
  if (!opt.bands.empty()) settings.bands = resolve_bands(file, band_names);
  settings.progress = !opt.quiet;

  std::filesystem::path exr = !opt.exr.empty() ? std::filesystem::path(opt.exr) : file.output.exr;
  if (exr.empty()) throw Error("no output file: give -o OUT.exr (or [output] exr = ... in the scene)");
  std::filesystem::path png = !opt.png.empty() ? std::filesystem::path(opt.png) : file.output.png;
  const std::filesystem::path checkpoint = exr.string() + ".checkpoint";

  // What the checkpoint must match to be resumed: everything that changes the samples.
  std::string key = fmt::format("sylva {} scene {} seed {} res {}x{} depth {} bands", SYLVA_VERSION, file.content_hash,
                                settings.seed, settings.width, settings.height, settings.integrator.max_depth);
  for (const auto& b : band_names) key += " " + b;

  const auto t0 = std::chrono::steady_clock::now();
  std::atomic<bool> stop{false};
  settings.cancel = &stop;
  Renderer renderer(file.scene, settings);
  const EmbreeStats& es = renderer.embree_stats();
  if (!opt.quiet)
    fmt::print(
        stderr,
        "scene: {} instances, {} unique triangles + {} leaf quads ({} + {} instanced); BVH {:.1f} MiB in {:.0f} ms\n",
        es.instances, es.triangles, es.leaf_quads, es.instanced_triangles, es.instanced_leaf_quads,
        es.bvh_bytes / 1048576.0, es.build_ms);
  Film film = opt.resume ? Film::load(checkpoint, key) : renderer.make_film();
  if (opt.resume && !opt.quiet)
    fmt::print(stderr, "resuming from {} ({} samples)\n", checkpoint.string(), film.total_samples());

  // Render in rounds: stop for a periodic checkpoint, or for good on SIGINT/SIGTERM.
  RenderStats total;
  while (true) {
    stop = false;
    std::atomic<bool> done{false};
    std::thread watcher([&] {
      const auto start = std::chrono::steady_clock::now();
      while (!done) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        const double minutes = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 60.0;
        if (g_interrupted || (opt.checkpoint_minutes > 0 && minutes >= opt.checkpoint_minutes)) {
          stop = true;
          return;
        }
      }
    });
    const RenderStats stats = renderer.render(film);
    done = true;
    watcher.join();
    total.samples += stats.samples;
    total.rays += stats.rays;
    total.seconds += stats.seconds;
    if (!stats.interrupted) break;
    film.save(checkpoint, key);
    if (g_interrupted) {
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      fmt::print(
          stderr,
          "\ninterrupted: checkpoint with {} samples written to {}; continue with the same command and --resume\n",
          film.total_samples(), checkpoint.string());
      return 130;
    }
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);

  Image image = renderer.make_image(film);
  annotate_render(image, file, settings);
  write_exr(exr, image);

  if (!png.empty()) {
    PreviewOptions preview;
    const bool has_rgb = image.find_channel("R") >= 0;
    const std::string grey = renderer.radiance_channels().front();
    if (!has_rgb) preview.channels = {grey, grey, grey};
    preview.view = opt.view.empty() ? file.output.view : opt.view;
    preview.exposure_ev = (opt.exposure_set ? opt.exposure : file.output.exposure_ev) +
                          (file.output.auto_exposure ? auto_exposure_ev(image, preview.channels) : 0.0f);
    write_png_preview(png, image, preview);
  }
  std::filesystem::remove(checkpoint);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!opt.quiet)
    fmt::print(stderr,
               "wrote {}{}: {} samples in {:.2f} s render ({:.2f} s total): {:.3f} M samples/s, {:.3f} M rays/s\n",
               exr.string(), png.empty() ? "" : " and " + png.string(), total.samples, total.seconds, wall,
               total.samples / std::max(1e-9, total.seconds) / 1e6, total.rays / std::max(1e-9, total.seconds) / 1e6);
  return 0;
}

}  // namespace

CommandRun add_render_command(CLI::App& parent) {
  auto opt = std::make_shared<RenderOptions>();
  CLI::App* cmd = parent.add_subcommand("render", "Render a scene file (or the built-in default scene) to EXR and PNG");
  cmd->add_option("scene", opt->scene, "Scene file (TOML); omit for the built-in default scene");
  cmd->add_option("-o,--output", opt->exr, "Output EXR (written atomically)");
  cmd->add_option("--png", opt->png, "PNG preview of the visible band (OCIO display transform)");
  cmd->add_option("--spp", opt->spp, "Samples per pixel")->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--res", opt->res, "Resolution WIDTHxHEIGHT");
  cmd->add_option("--threads", opt->threads, "Worker threads (0 = all)")->check(CLI::Range(0, 4096));
  cmd->add_option("--seed", opt->seed, "Random seed")->check(CLI::Range(int64_t{0}, INT64_MAX));
  cmd->add_option("--bands", opt->bands, "Comma-separated bands, e.g. rgb,nir,S2A_B8");
  cmd->add_option("--max-depth", opt->max_depth, "Maximum path depth")->check(CLI::Range(1, 1024));
  cmd->add_option("--checkpoint-minutes", opt->checkpoint_minutes,
                  "Write a checkpoint this often (0 = only on interrupt)")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--exposure", opt->exposure, "Preview exposure offset in stops")->each([opt](const std::string&) {
    opt->exposure_set = true;
  });
  cmd->add_option("--view", opt->view, "Preview view transform (Standard, ACES, Raw)");
  cmd->add_flag("--resume", opt->resume, "Continue from OUT.exr.checkpoint (left by an interrupted render)");
  cmd->add_flag("-q,--quiet", opt->quiet, "No progress bar or summary");
  return [opt] { return run_render(*opt); };
}

}  // namespace sylva

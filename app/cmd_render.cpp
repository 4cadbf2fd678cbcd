// `sylva render`: scene file (or the built-in default) → multi-channel EXR + PNG preview.

#include "app/commands.h"
#include "core/color.h"
#include "core/error.h"
#include "core/image.h"
#include "render/renderer.h"
#include "render/session.h"
#include "scenes/scene_file.h"

#include <fmt/core.h>

#include <chrono>

namespace sylva {

namespace {

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
  const InterruptHandlers interrupt_handlers;
  SceneFile file = opt.scene.empty() ? default_scene() : load_scene_file(opt.scene);
  if (!opt.quiet)
    for (const std::string& w : file.warnings) fmt::print(stderr, "{}\n", w);
  // The scene file's settings, with the command line's overrides on top.
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
  if (!opt.bands.empty()) settings.bands = resolve_bands(file, split_list(opt.bands));
  settings.progress = !opt.quiet;

  std::filesystem::path exr = !opt.exr.empty() ? std::filesystem::path(opt.exr) : file.output.exr;
  if (exr.empty()) throw Error("no output file: give -o OUT.exr (or [output] exr = ... in the scene)");
  std::filesystem::path png = !opt.png.empty() ? std::filesystem::path(opt.png) : file.output.png;

  const auto t0 = std::chrono::steady_clock::now();
  const EmbreeScene embree(file.scene);
  const EmbreeStats& es = embree.stats();
  if (!opt.quiet)
    fmt::print(
        stderr,
        "scene: {} instances, {} unique triangles + {} leaf quads ({} + {} instanced); BVH {:.1f} MiB in {:.0f} ms\n",
        es.instances, es.triangles, es.leaf_quads, es.instanced_triangles, es.instanced_leaf_quads,
        es.bvh_bytes / 1048576.0, es.build_ms);
  SessionOptions session_options;
  session_options.checkpoint = exr.string() + ".checkpoint";
  session_options.key = checkpoint_key(file.content_hash, settings);
  session_options.resume = opt.resume;
  session_options.checkpoint_minutes = opt.checkpoint_minutes;
  session_options.interrupt = &InterruptHandlers::flag();
  RenderSession session(file.scene, embree, settings, session_options);
  if (opt.resume && !opt.quiet)
    fmt::print(stderr, "resuming from {} ({} samples)\n", session_options.checkpoint.string(),
               session.resumed_samples());

  const SessionResult result = session.run();
  const RenderStats& total = result.stats;
  if (result.interrupted) {
    fmt::print(stderr,
               "\ninterrupted: checkpoint with {} samples written to {}; continue with the same command and --resume\n",
               result.film.total_samples(), session_options.checkpoint.string());
    return 130;
  }

  const Renderer& renderer = session.renderer();
  Image image = renderer.make_image(result.film);
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
  session.remove_checkpoint();
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

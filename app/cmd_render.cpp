// `sylva render`: scene file (or the built-in default) → multi-channel EXR + PNG preview; or one
// chunk of a split render → a partial file (`--chunk i/N`, merged by `sylva merge`); or the frames
// of a wind animation (`--frames A:B --fps F`), one EXR per frame. Parses the options and calls
// the render call (pipeline/render_call.h); signals cancel it through the observer.

#include "app/cli_observer.h"
#include "app/commands.h"
#include "core/error.h"
#include "pipeline/render_call.h"

#include <fmt/core.h>

namespace sylva {

namespace {

struct RenderOptions {
  RenderCallOptions call;
  bool quiet = false;
  float exposure = 0.0f;
  bool exposure_set = false;
  bool no_memory_check = false;
  std::string frames;
  double fps = 24.0;
};

int run_render(RenderOptions opt) {
  // While the scene loads and its BVH is built, SIGINT/SIGTERM end the process at once (nothing
  // has been written); once rendering starts they stop it cleanly with a checkpoint.
  const InterruptHandlers interrupt_handlers(InterruptHandlers::OnSignal::exit);
  CliObserver observer(opt.quiet);
  RenderCallOptions& call = opt.call;
  call.progress_bar = !opt.quiet;
  call.require_exr = true;
  call.memory_check = !opt.no_memory_check;
  if (opt.exposure_set) call.preview.exposure_ev = opt.exposure;
  // `sylva render` alone: the built-in scene to ./sylva.exr and ./sylva.png.
  if (call.request.source.file.empty() && call.request.source.text.empty() && call.exr.empty() && call.chunk.empty()) {
    call.exr = "sylva.exr";
    if (call.png.empty()) call.png = "sylva.png";
  }
  if (!opt.frames.empty()) {
    const FramesResult r = render_frames(call, parse_frames(opt.frames, opt.fps), observer);
    if (r.skipped > 0) observer.on_message(fmt::format("{} frame(s) already rendered, skipped", r.skipped));
    return r.last.status == RenderStatus::finished ? 0 : report_interrupted(r.last);
  }
  const RenderResult r = render_scene(call, observer);
  if (r.status != RenderStatus::finished) return report_interrupted(r);
  const std::string what =
      call.chunk.empty() ? r.outputs.exr.string() + (r.outputs.png.empty() ? "" : " and " + r.outputs.png.string())
                         : fmt::format("{} (chunk {} by {})", r.outputs.exr.string(), call.chunk, call.split);
  observer.on_message(summary_line(what, r));
  return 0;
}

}  // namespace

CommandRun add_render_command(CLI::App& parent) {
  auto opt = std::make_shared<RenderOptions>();
  RenderCallOptions& call = opt->call;
  RenderRequest& req = call.request;
  CLI::App* cmd = parent.add_subcommand("render", "Render a scene file (or the built-in default scene) to EXR and PNG");
  cmd->add_option("scene", req.source.file, "Scene file (TOML); omit for the built-in default scene");
  cmd->add_option("-o,--output", call.exr,
                  "Output EXR, or partial file with --chunk (written atomically); the built-in scene: sylva.exr");
  cmd->add_option("--png", call.png, "PNG preview of the visible band (OCIO display transform)");
  add_request_options(cmd, req);
  cmd->add_option("--checkpoint-minutes", call.checkpoint_minutes,
                  "Write a checkpoint this often (0 = only on interrupt)")
      ->check(kFiniteNumber & CLI::Range(0.0, 1e6));
  cmd->add_option("--exposure", opt->exposure, "Preview exposure offset in stops")
      ->check(kFiniteNumber & CLI::Range(-64.0, 64.0))
      ->each([opt](const std::string&) { opt->exposure_set = true; });
  cmd->add_option("--view", call.preview.view, "Preview view transform (Standard, ACES, Raw)");
  cmd->add_flag("--features", req.features,
                "Also write the denoiser's features and half-buffers (feature.*, even.*, odd.*; docs/denoise.md)");
  cmd->add_flag("--material-ids", req.material_ids,
                "Also write id.material (the first hit's material + 1, 0 = sky): compare tests each material's pixels");
  cmd->add_flag("--denoise", call.denoise,
                "Denoise the image (implies --features): the beauty denoised, the noisy one kept as noisy.*");
  cmd->add_flag("--resume", call.resume, "Continue from OUT.exr.checkpoint (left by an interrupted render)");
  cmd->add_option("--chunk", call.chunk, "Render only chunk i/N (0 <= i < N) to a partial file for sylva merge");
  cmd->add_option("--split", call.split, "How --chunk splits the work: samples (default) or tiles (bands of rows)")
      ->check(CLI::IsMember({"samples", "tiles"}));
  cmd->add_option("--frames", opt->frames,
                  "Render frames FIRST:LAST of the trees' wind animation, one OUT.NNNN.exr each; existing frames "
                  "are skipped");
  cmd->add_option("--fps", opt->fps, "Frames per second of --frames (wind time = frame / fps)")
      ->check(kFiniteNumber & CLI::Range(1e-6, 1e6));
  cmd->add_flag("--no-memory-check", opt->no_memory_check,
                "Render even when the estimated memory (film, image, BVH) exceeds what is available");
  cmd->add_flag("-q,--quiet", opt->quiet, "No progress (bar or log lines) or summary");
  return [opt] { return run_render(*opt); };
}

}  // namespace sylva

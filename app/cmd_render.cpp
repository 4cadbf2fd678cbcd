// `sylva render`: scene file (or the built-in default) → multi-channel EXR + PNG preview; or one
// chunk of a split render → a partial file (`--chunk i/N`, merged by `sylva merge`); or the frames
// of a wind animation (`--frames A:B --fps F`), one EXR per frame.

#include "app/commands.h"
#include "app/render_job.h"
#include "core/color.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/output_paths.h"
#include "render/chunk.h"
#include "render/renderer.h"
#include "render/session.h"
#include "scenes/sidecar.h"

#include <fmt/core.h>

#include <chrono>
#include <optional>

namespace sylva {

namespace {

struct RenderOptions {
  RenderRequest request;
  std::string exr;
  std::string png;
  bool quiet = false;
  bool resume = false;
  double checkpoint_minutes = 10.0;
  float exposure = 0.0f;
  bool exposure_set = false;
  PreviewOverrides preview;
  std::string chunk;
  std::string split = "samples";
  std::string frames;
  double fps = 24.0;
  bool no_memory_check = false;
};

std::filesystem::path checkpoint_of(const std::filesystem::path& exr) { return checkpoint_path_for(exr); }

// Everything that can be checked before the scene's BVH is built and a sample rendered: the outputs
// (core/output_paths.h) against each other and every input of the scene, the preview's view, and
// the memory the render needs against what is available (unless --no-memory-check).
void check_before_rendering(const RenderOptions& opt, const RenderJob& job, const std::filesystem::path& exr,
                            const std::filesystem::path& png, bool chunk) {
  std::vector<OutputFile> outputs{{"-o", exr}};
  if (!chunk)
    outputs.insert(outputs.end(),
                   {{"--png", png}, {"checkpoint", checkpoint_of(exr)}, {"label sidecar", sidecar_path(exr)}});
  check_outputs(outputs, job.file.inputs);
  if (!png.empty()) check_preview_view(opt.preview.view.empty() ? job.file.output.view : opt.preview.view);
  if (opt.no_memory_check) return;
  const MemoryEstimate need = estimate_render_memory(job.file.scene, job.settings);
  const uint64_t available = available_memory_bytes();
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  if (need.total() > available)
    throw Error(fmt::format(
        "the render needs about {:.2f} GiB (film {:.2f}, image {:.2f}, BVH {:.2f}) but only {:.2f} "
        "GiB are available; lower --res or the number of bands, or try anyway with "
        "--no-memory-check (docs/limits.md)",
        need.total() / kGiB, need.film_bytes / kGiB, need.image_bytes / kGiB, need.bvh_bytes / kGiB, available / kGiB));
}

void print_scene_stats(const EmbreeStats& es) {
  fmt::print(stderr,
             "scene: {} instances, {} unique triangles + {} leaf quads + {} curves ({} + {} + {} instanced); BVH "
             "{:.1f} MiB in {:.0f} ms (and {:.1f} MiB of vertices shared with the scene), Embree's {} kernels\n",
             es.instances, es.triangles, es.leaf_quads, es.curves, es.instanced_triangles, es.instanced_leaf_quads,
             es.instanced_curves, es.bvh_bytes / 1048576.0, es.build_ms, es.shared_vertex_bytes / 1048576.0,
             embree_isa_name(es.isa));
}

void print_summary(const std::string& what, const RenderStats& total, double wall) {
  const ResidentMemory memory = resident_memory();
  fmt::print(stderr,
             "wrote {}: {} samples in {:.2f} s render ({:.2f} s total): {:.3f} M samples/s, {:.3f} M rays/s "
             "({:.2f} CPU-s: {:.3f} M rays per CPU-second); {:.0f} MiB resident, {:.0f} MiB of it in huge pages\n",
             what, total.samples, total.seconds, wall, total.samples / std::max(1e-9, total.seconds) / 1e6,
             total.rays / std::max(1e-9, total.seconds) / 1e6, total.cpu_seconds,
             total.rays / std::max(1e-9, total.cpu_seconds) / 1e6, memory.bytes / 1048576.0,
             memory.huge_page_bytes / 1048576.0);
}

// One image: a session that checkpoints and resumes. Returns the exit code.
int render_image(const RenderOptions& opt, const RenderJob& job, const std::filesystem::path& exr,
                 const std::filesystem::path& png, bool resume) {
  const auto t0 = std::chrono::steady_clock::now();
  check_before_rendering(opt, job, exr, png, false);
  if (!opt.quiet)
    for (const std::string& w : job.file.warnings) fmt::print(stderr, "{}\n", w);
  const EmbreeScene embree(job.file.scene, bvh_build_for(job.settings), job.settings.isa);
  if (!opt.quiet) print_scene_stats(embree.stats());
  SessionOptions session_options;
  session_options.checkpoint = checkpoint_of(exr);
  session_options.key = checkpoint_key(job.file.content_hash, job.settings);
  session_options.resume = resume;
  session_options.checkpoint_minutes = opt.checkpoint_minutes;
  session_options.interrupt = &InterruptHandlers::flag();
  session_options.warn = [](const std::string& message) { fmt::print(stderr, "\n{}\n", message); };
  RenderSession session(job.file.scene, embree, job.settings, session_options);
  if (resume && !opt.quiet)
    fmt::print(stderr, "resuming from {} ({} samples)\n", session_options.checkpoint.string(),
               session.resumed_samples());

  // From here on a signal stops the render cleanly: a checkpoint is written.
  InterruptHandlers::set(InterruptHandlers::OnSignal::set_flag);
  const SessionResult result = session.run();
  if (result.interrupted) {
    fmt::print(stderr,
               "\ninterrupted: checkpoint with {} samples written to {}; continue with the same command and --resume\n",
               result.film.total_samples(), session_options.checkpoint.string());
    return 130;
  }
  // The finished film is saved first, so an output that cannot be written (or a signal during the
  // write) loses no samples: `--resume` then only writes the outputs.
  session.save_checkpoint(result.film);
  try {
    write_render_outputs(session.renderer(), result.film, job, exr, png, opt.preview);
  } catch (const Error& e) {
    throw Error(
        fmt::format("{}\nthe rendered samples are kept in {}: fix the output and run the same command with "
                    "--resume to write it",
                    e.what(), session_options.checkpoint.string()));
  }
  if (InterruptHandlers::flag()) {
    fmt::print(stderr, "\ninterrupted while writing the outputs: {} kept; run the same command with --resume\n",
               session_options.checkpoint.string());
    return 130;
  }
  session.remove_checkpoint();
  if (!opt.quiet)
    print_summary(exr.string() + (png.empty() ? "" : " and " + png.string()), result.stats,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

// One chunk of a split render: its pixels and samples, saved as a partial file.
int render_chunk(const RenderOptions& opt, RenderJob job, const std::filesystem::path& out) {
  if (!opt.png.empty()) throw Error("--chunk writes a partial file; give --png to sylva merge");
  if (opt.resume) throw Error("--chunk renders cannot be resumed; render the chunk again");
  const auto t0 = std::chrono::steady_clock::now();
  const ChunkSpec spec = parse_chunk(opt.chunk, opt.split);
  if (!opt.quiet)
    for (const std::string& w : job.file.warnings) fmt::print(stderr, "{}\n", w);
  const ChunkWork work = chunk_work(spec, job.settings.width, job.settings.height, job.settings.spp);
  check_before_rendering(opt, job, out, {}, true);
  job.settings.cancel = &InterruptHandlers::flag();
  const EmbreeScene embree(job.file.scene, bvh_build_for(job.settings), job.settings.isa);
  if (!opt.quiet) print_scene_stats(embree.stats());
  InterruptHandlers::set(InterruptHandlers::OnSignal::set_flag);
  Renderer renderer(job.file.scene, embree, job.settings);
  Film film = renderer.make_film(work.region, work.samples.first);
  const RenderStats stats = renderer.render(film, work.region, work.samples);
  if (stats.interrupted) {
    fmt::print(stderr, "\ninterrupted: chunk {} not written\n", opt.chunk);
    return 130;
  }
  PartialHeader header;
  header.key = checkpoint_key(job.file.content_hash, job.settings);
  header.chunk = spec;
  header.spp = job.settings.spp;
  header.job = describe_job(opt.request, job);
  save_partial(out, header, film);
  if (!opt.quiet)
    print_summary(fmt::format("{} (chunk {}/{} by {})", out.string(), spec.index, spec.count, opt.split), stats,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

// OUT.exr → OUT.0007.exr (at least four digits).
std::filesystem::path frame_path(const std::filesystem::path& p, int frame) {
  if (p.empty()) return p;
  std::filesystem::path out = p;
  out.replace_filename(fmt::format("{}.{:04d}{}", p.stem().string(), frame, p.extension().string()));
  return out;
}

// Frames A..B (inclusive) of a wind animation; frames whose outputs exist are skipped.
int render_frames(const RenderOptions& opt, const std::filesystem::path& exr, const std::filesystem::path& png) {
  int first = 0, last = 0;
  char extra = 0;
  if (std::sscanf(opt.frames.c_str(), "%d:%d%c", &first, &last, &extra) != 2 || first < 0 || last < first ||
      last > 9999999)
    throw Error("--frames: expected FIRST:LAST with 0 <= FIRST <= LAST, e.g. 0:239, not '" + opt.frames + "'");
  if (!opt.chunk.empty()) throw Error("--frames and --chunk cannot be combined");
  int skipped = 0;
  for (int frame = first; frame <= last; ++frame) {
    const std::filesystem::path frame_exr = frame_path(exr, frame), frame_png = frame_path(png, frame);
    // Outputs are written atomically, so an existing file is a complete one.
    if (std::filesystem::exists(frame_exr) && (frame_png.empty() || std::filesystem::exists(frame_png))) {
      ++skipped;
      continue;
    }
    RenderRequest request = opt.request;
    request.time_s = frame / opt.fps;
    if (!opt.quiet) fmt::print(stderr, "frame {} (t = {:.4f} s)\n", frame, *request.time_s);
    const bool resume = opt.resume && std::filesystem::exists(checkpoint_of(frame_exr));
    InterruptHandlers::set(InterruptHandlers::OnSignal::exit);
    const int code = render_image(opt, prepare_render(request), frame_exr, frame_png, resume);
    if (code != 0) return code;
  }
  if (!opt.quiet && skipped > 0) fmt::print(stderr, "{} frame(s) already rendered, skipped\n", skipped);
  return 0;
}

int run_render(RenderOptions opt) {
  // While the scene loads and its BVH is built, SIGINT/SIGTERM end the process at once (nothing
  // has been written); once rendering starts they stop it cleanly with a checkpoint.
  const InterruptHandlers interrupt_handlers(InterruptHandlers::OnSignal::exit);
  opt.request.progress = !opt.quiet;
  if (opt.exposure_set) opt.preview.exposure_ev = opt.exposure;
  // The outputs named on the command line, against the scene file, before it is even loaded.
  check_outputs({{"-o", opt.exr}, {"--png", opt.png}}, {opt.request.scene});
  // Frames assemble the scene once per frame (and here only for the scene's output names); the
  // other renders once, here.
  std::optional<RenderJob> job;
  if (opt.frames.empty() || opt.exr.empty() || (opt.png.empty() && opt.chunk.empty())) {
    const auto load_start = std::chrono::steady_clock::now();
    job = prepare_render(opt.request);
    if (!opt.quiet)
      fmt::print(stderr, "scene loaded in {:.2f} s\n",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count());
  }
  const std::filesystem::path exr = !opt.exr.empty() ? std::filesystem::path(opt.exr) : job->file.output.exr;
  const std::filesystem::path png =
      !opt.png.empty() || !opt.chunk.empty() ? std::filesystem::path(opt.png) : job->file.output.png;
  if (exr.empty()) throw Error("no output file: give -o OUT.exr (or [output] exr = ... in the scene)");
  if (!opt.frames.empty()) return render_frames(opt, exr, png);
  if (!opt.chunk.empty()) return render_chunk(opt, std::move(*job), exr);
  return render_image(opt, *job, exr, png, opt.resume);
}

}  // namespace

CommandRun add_render_command(CLI::App& parent) {
  auto opt = std::make_shared<RenderOptions>();
  RenderRequest& req = opt->request;
  CLI::App* cmd = parent.add_subcommand("render", "Render a scene file (or the built-in default scene) to EXR and PNG");
  cmd->add_option("scene", req.scene, "Scene file (TOML); omit for the built-in default scene");
  cmd->add_option("-o,--output", opt->exr, "Output EXR, or partial file with --chunk (written atomically)");
  cmd->add_option("--png", opt->png, "PNG preview of the visible band (OCIO display transform)");
  cmd->add_option("--spp", req.spp, "Samples per pixel")->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--res", req.res, "Resolution WIDTHxHEIGHT");
  cmd->add_option("--threads", req.threads, "Worker threads (0 = all)")->check(CLI::Range(0, 4096));
  cmd->add_option("--seed", req.seed, "Random seed")->check(kUint64 & CLI::Range(int64_t{0}, INT64_MAX));
  cmd->add_option("--bands", req.bands, "Comma-separated bands, e.g. rgb,nir,S2A_B8");
  cmd->add_option("--max-depth", req.max_depth, "Maximum path depth")->check(CLI::Range(1, 1024));
  cmd->add_option("--quantity", req.quantity, "Band channels as radiance or reflectance (factor)")
      ->check(CLI::IsMember({"radiance", "reflectance"}));
  cmd->add_option("--isa", req.isa,
                  "Embree's kernels, at most: sse2, sse4.2, avx, avx2 (default: the same bits on every processor "
                  "with AVX2), avx512, or native (the processor's widest)")
      ->check(CLI::IsMember(embree_isa_names()));
  cmd->add_option("--checkpoint-minutes", opt->checkpoint_minutes,
                  "Write a checkpoint this often (0 = only on interrupt)")
      ->check(kFiniteNumber & CLI::Range(0.0, 1e6));
  cmd->add_option("--exposure", opt->exposure, "Preview exposure offset in stops")
      ->check(kFiniteNumber & CLI::Range(-64.0, 64.0))
      ->each([opt](const std::string&) { opt->exposure_set = true; });
  cmd->add_option("--view", opt->preview.view, "Preview view transform (Standard, ACES, Raw)");
  cmd->add_flag("--resume", opt->resume, "Continue from OUT.exr.checkpoint (left by an interrupted render)");
  cmd->add_option("--chunk", opt->chunk, "Render only chunk i/N (0 <= i < N) to a partial file for sylva merge");
  cmd->add_option("--split", opt->split, "How --chunk splits the work: samples (default) or tiles (bands of rows)")
      ->check(CLI::IsMember({"samples", "tiles"}));
  cmd->add_option("--frames", opt->frames,
                  "Render frames FIRST:LAST of the trees' wind animation, one OUT.NNNN.exr each; existing frames "
                  "are skipped");
  cmd->add_option("--fps", opt->fps, "Frames per second of --frames (wind time = frame / fps)")
      ->check(kFiniteNumber & CLI::Range(1e-6, 1e6));
  cmd->add_flag("--no-memory-check", opt->no_memory_check,
                "Render even when the estimated memory (film, image, BVH) exceeds what is available");
  cmd->add_flag("-q,--quiet", opt->quiet, "No progress bar or summary");
  return [opt] { return run_render(*opt); };
}

}  // namespace sylva

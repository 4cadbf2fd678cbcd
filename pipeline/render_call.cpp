#include "pipeline/render_call.h"

#include "core/error.h"
#include "core/output_paths.h"
#include "denoise/denoise_image.h"
#include "pipeline/sensor_stage.h"
#include "render/session.h"
#include "scenes/sidecar.h"

#include <fmt/core.h>

#include <chrono>
#include <cstdio>
#include <utility>

namespace sylva {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The image the outputs are written from: annotated, and denoised when asked.
Image output_image(const Renderer& renderer, const Film& film, const SceneFile& file, const RenderCallOptions& options,
                   RenderObserver& observer) {
  Image image = annotated_image(renderer, film, file);
  if (!options.denoise) return image;
  DenoiseSettings settings;
  settings.threads = renderer.settings().threads;
  DenoiseStats stats;
  image = denoise_image(image, settings, &stats);
  observer.on_message(fmt::format("denoised in {:.2f} s", stats.seconds));
  return image;
}

// The scene's [sensor] applied to the finished image and written beside its outputs.
Image sense(const SceneFile& file, const RenderSettings& settings, const Image& image, const OutputPaths& outputs,
            RenderObserver& observer) {
  SensedImage sensed = run_sensor_stage(file, settings, image, outputs.exr, outputs.png);
  if (sensed.image.pixels.empty()) return {};
  observer.on_message(
      fmt::format("sensor: {}x{} detectors ({:.3g} render pixels each, GSD {:.3g} m), {:.3g} ms "
                  "integration, in {:.2f} s",
                  sensed.grid.width, sensed.grid.height, sensed.grid.ratio, sensed.gsd_m,
                  sensed.integration_time_s * 1e3, sensed.seconds));
  return std::move(sensed.image);
}

std::string scene_stats_line(const EmbreeStats& es) {
  return fmt::format(
      "scene: {} instances, {} unique triangles + {} leaf quads + {} curves ({} + {} + {} instanced); BVH "
      "{:.1f} MiB in {:.0f} ms (and {:.1f} MiB of vertices shared with the scene), Embree's {} kernels",
      es.instances, es.triangles, es.leaf_quads, es.curves, es.instanced_triangles, es.instanced_leaf_quads,
      es.instanced_curves, es.bvh_bytes / 1048576.0, es.build_ms, es.shared_vertex_bytes / 1048576.0,
      embree_isa_name(es.isa));
}

// The settings the render runs with: the observer's progress and (for chunks) its cancel flag.
void observe(RenderSettings& settings, const RenderCallOptions& options, RenderObserver& observer) {
  settings.progress = options.progress_bar;
  settings.on_progress = [&observer](const ProgressReport& report) { observer.on_progress(report); };
}

// A film made by the caller's seam (sylva-mpi), or rendered in memory (no checkpoint: a renderer
// polling the observer's flag, with the seams' faults), then the outputs.
RenderResult render_film(const LoadedScene& loaded, RenderSettings settings, const RenderCallOptions& options,
                         RenderObserver& observer, RenderResult result) {
  const SceneFile& file = loaded.job.file;
  observer.on_phase(RenderPhase::rendering);
  settings.cancel = &observer.cancel_flag();
  Renderer renderer(file.scene, *loaded.embree, settings, options.seams.faults);
  Film film;
  if (options.seams.film_source) {
    film = options.seams.film_source(renderer, observer);
  } else {
    film = renderer.make_film();
    result.stats = renderer.render(film);
  }
  result.film_samples = film.total_samples();
  if (result.stats.interrupted) {
    result.status = RenderStatus::interrupted;
    return result;
  }
  observer.on_phase(RenderPhase::writing);
  result.image = output_image(renderer, film, file, options, observer);
  if (!result.outputs.exr.empty())
    write_render_outputs(renderer, result.image, file, result.outputs.exr, result.outputs.png, options.preview);
  result.sensor = sense(file, renderer.settings(), result.image, result.outputs, observer);
  return result;
}

// One image: a session that checkpoints and resumes.
RenderResult render_image(const LoadedScene& loaded, const RenderSettings& settings, const RenderCallOptions& options,
                          RenderObserver& observer, RenderResult result) {
  const SceneFile& file = loaded.job.file;
  const OutputPaths& outputs = result.outputs;
  SessionOptions session_options;
  session_options.checkpoint = outputs.checkpoint;
  session_options.key = checkpoint_key(file.content_hash, settings);
  session_options.resume = options.resume;
  session_options.checkpoint_minutes = options.checkpoint_minutes;
  session_options.interrupt = &observer.cancel_flag();
  session_options.warn = [&observer](const std::string& message) { observer.on_warning(message); };
  RenderSession session(file.scene, *loaded.embree, settings, session_options);
  result.resumed_samples = session.resumed_samples();
  if (options.resume)
    observer.on_message(
        fmt::format("resuming from {} ({} samples)", outputs.checkpoint.string(), result.resumed_samples));

  observer.on_phase(RenderPhase::rendering);
  SessionResult rendered = session.run();
  result.stats = rendered.stats;
  result.film_samples = rendered.film.total_samples();
  if (rendered.interrupted) {
    result.status = RenderStatus::interrupted;
    return result;
  }
  // The finished film is saved first, so an output that cannot be written (or a cancel during the
  // write) loses no samples: resuming then only writes the outputs.
  session.save_checkpoint(rendered.film);
  observer.on_phase(RenderPhase::writing);
  result.image = output_image(session.renderer(), rendered.film, file, options, observer);
  try {
    write_render_outputs(session.renderer(), result.image, file, outputs.exr, outputs.png, options.preview);
    result.sensor = sense(file, session.renderer().settings(), result.image, outputs, observer);
  } catch (const Error& e) {
    throw Error(
        fmt::format("{}\nthe rendered samples are kept in {}: fix the output and run the same command with "
                    "--resume to write it",
                    e.what(), outputs.checkpoint.string()));
  }
  if (observer.cancel_flag()) {
    result.status = RenderStatus::interrupted_writing;
    return result;
  }
  session.remove_checkpoint();
  return result;
}

// One chunk of a split render: its pixels and samples, saved as a partial file.
RenderResult render_chunk(const LoadedScene& loaded, RenderSettings settings, const RenderCallOptions& options,
                          RenderObserver& observer, RenderResult result) {
  const SceneFile& file = loaded.job.file;
  const ChunkSpec spec = parse_chunk(options.chunk, options.split);
  const ChunkWork work = chunk_work(spec, settings.width, settings.height, settings.spp);
  PartialHeader header;
  header.key = checkpoint_key(file.content_hash, settings);
  header.chunk = spec;
  header.spp = settings.spp;
  header.job = describe_job(options.request, settings);  // before rendering: it may refuse the request
  settings.cancel = &observer.cancel_flag();
  observer.on_phase(RenderPhase::rendering);
  Renderer renderer(file.scene, *loaded.embree, settings);
  Film film = renderer.make_film(work.region, work.samples.first);
  result.stats = renderer.render(film, work.region, work.samples);
  result.film_samples = film.total_samples();
  if (result.stats.interrupted) {
    result.status = RenderStatus::interrupted;
    return result;
  }
  observer.on_phase(RenderPhase::writing);
  save_partial(result.outputs.exr, header, film);
  return result;
}

}  // namespace

LoadedScene load_render(const RenderCallOptions& options, RenderObserver& observer) {
  const auto t0 = Clock::now();
  const bool chunk = !options.chunk.empty();
  if (chunk && !options.png.empty()) throw Error("--chunk writes a partial file; give --png to sylva merge");
  if (chunk && options.resume) throw Error("--chunk renders cannot be resumed; render the chunk again");
  if (chunk && options.denoise)
    throw Error("--chunk writes a partial file; give --denoise to sylva merge (render the chunks with --features)");
  if (chunk && (options.seams.film_source || options.seams.modify_scene))
    throw Error("a chunk of a split render is rendered from the scene as its file says");
  // The outputs named by the caller, against the scene file, before it is even loaded.
  check_outputs({{"-o", options.exr}, {"--png", options.png}}, {options.request.source.file});
  if (chunk) parse_chunk(options.chunk, options.split);

  observer.on_phase(RenderPhase::loading);
  LoadedScene loaded;
  RenderJob& job = loaded.job;
  job = prepare_render(options.request);
  const RenderSeams& seams = options.seams;
  if (seams.modify_scene) seams.modify_scene(job.file.scene);
  if (seams.isa) job.settings.isa = *seams.isa;
  if (seams.adjust_settings) seams.adjust_settings(job.settings);
  if (options.denoise) job.settings.features = true;
  observe(job.settings, options, observer);
  observer.on_message(fmt::format("scene loaded in {:.2f} s", seconds_since(t0)));
  for (const std::string& w : job.file.warnings) observer.on_message(w);

  OutputPaths& outputs = loaded.outputs;
  outputs.exr = !options.exr.empty() ? options.exr : job.file.output.exr;
  if (outputs.exr.empty() && (options.require_exr || chunk))
    throw Error("no output file: give -o OUT.exr (or [output] exr = ... in the scene)");
  if (!chunk) {
    outputs.png = !options.png.empty() ? options.png : job.file.output.png;
    if (outputs.exr.empty() && !outputs.png.empty())
      throw Error("a PNG preview needs an EXR beside it: give -o OUT.exr (or [output] exr = ... in the scene)");
    if (!outputs.exr.empty() && !seams.film_source) outputs.checkpoint = checkpoint_path_for(outputs.exr);
    if (!outputs.exr.empty()) outputs.sidecar = sidecar_path(outputs.exr);
  }
  check_render_outputs(job, outputs, options.preview, options.memory_check);
  // A chunk writes no sensor files (the merge applies the sensor) but is refused what the sensor
  // cannot take, before it renders.
  check_sensor_stage(job, chunk ? std::filesystem::path() : outputs.exr, outputs.png);
  if (options.resume && outputs.checkpoint.empty()) throw Error("--resume needs an output EXR (its checkpoint)");
  const bool faults = seams.faults.mis_weight_one || seams.faults.no_shadow_alpha;
  if (faults && !outputs.checkpoint.empty()) throw Error("transport faults are for renders kept in memory");

  loaded.embree = std::make_unique<const EmbreeScene>(
      job.file.scene, seams.faults, seams.bvh.value_or(bvh_build_for(job.settings)), job.settings.isa);
  observer.on_message(scene_stats_line(loaded.embree->stats()));
  loaded.load_seconds = seconds_since(t0);
  return loaded;
}

RenderResult render_loaded(const LoadedScene& loaded, const RenderCallOptions& options, RenderObserver& observer,
                           const std::function<void(RenderSettings&)>& per_render) {
  const auto t0 = Clock::now();
  RenderSettings settings = loaded.job.settings;
  if (per_render) per_render(settings);
  RenderResult result;
  result.outputs = loaded.outputs;
  result.load_seconds = loaded.load_seconds;
  if (!options.chunk.empty())
    result = render_chunk(loaded, std::move(settings), options, observer, std::move(result));
  else if (result.outputs.checkpoint.empty())
    result = render_film(loaded, std::move(settings), options, observer, std::move(result));
  else
    result = render_image(loaded, settings, options, observer, std::move(result));
  result.total_seconds = loaded.load_seconds + seconds_since(t0);
  return result;
}

RenderResult render_scene(const SceneSource& source, RenderCallOptions options, RenderObserver& observer) {
  options.request.source = source;
  return render_scene(options, observer);
}

RenderResult render_scene(const RenderCallOptions& options, RenderObserver& observer) {
  const LoadedScene loaded = load_render(options, observer);
  return render_loaded(loaded, options, observer);
}

FrameRange parse_frames(const std::string& text, double fps) {
  FrameRange r;
  r.fps = fps;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%d:%d%c", &r.first, &r.last, &extra) != 2 || r.first < 0 || r.last < r.first ||
      r.last > 9999999)
    throw Error("--frames: expected FIRST:LAST with 0 <= FIRST <= LAST, e.g. 0:239, not '" + text + "'");
  return r;
}

std::filesystem::path frame_path(const std::filesystem::path& p, int frame) {
  if (p.empty()) return p;
  std::filesystem::path out = p;
  out.replace_filename(fmt::format("{}.{:04d}{}", p.stem().string(), frame, p.extension().string()));
  return out;
}

FramesResult render_frames(const RenderCallOptions& options, const FrameRange& frames, RenderObserver& observer) {
  if (!options.chunk.empty()) throw Error("--frames and --chunk cannot be combined");
  // The output names: the caller's, else the scene's [output] (the scene is assembled again for
  // every frame, at its own wind time).
  std::filesystem::path exr = options.exr, png = options.png;
  if (exr.empty() || png.empty()) {
    const RenderJob job = prepare_render(options.request);
    if (exr.empty()) exr = job.file.output.exr;
    if (png.empty() && options.png.empty()) png = job.file.output.png;
  }
  if (exr.empty()) throw Error("no output file: give -o OUT.exr (or [output] exr = ... in the scene)");
  FramesResult out;
  for (int frame = frames.first; frame <= frames.last; ++frame) {
    RenderCallOptions o = options;
    o.exr = frame_path(exr, frame);
    o.png = frame_path(png, frame);
    if (std::filesystem::exists(o.exr) && (o.png.empty() || std::filesystem::exists(o.png))) {
      ++out.skipped;
      continue;
    }
    o.request.time_s = frame / frames.fps;
    o.resume = options.resume && std::filesystem::exists(checkpoint_path_for(o.exr));
    observer.on_message(fmt::format("frame {} (t = {:.4f} s)", frame, *o.request.time_s));
    out.last = render_scene(o, observer);
    if (out.last.status != RenderStatus::finished) return out;
    ++out.rendered;
  }
  return out;
}

MergeResult merge_parts(const std::vector<std::filesystem::path>& parts, bool allow_missing,
                        const RenderCallOptions& options, RenderObserver& observer) {
  const auto t0 = Clock::now();
  MergeResult out;
  OutputPaths& outputs = out.render.outputs;
  outputs.exr = options.exr;
  outputs.png = options.png;
  outputs.sidecar = options.exr.empty() ? std::filesystem::path() : sidecar_path(options.exr);
  const std::vector<OutputFile> checked{
      {"-o", outputs.exr}, {"--png", outputs.png}, {"label sidecar", outputs.sidecar}};
  check_outputs(checked, parts);
  observer.on_phase(RenderPhase::loading);
  MergedParts merged = merge_partials(parts, allow_missing);
  RenderRequest request = request_from_job(merged.header.job, merged.header.spp);
  request.threads = options.request.threads;
  const RenderJob job = prepare_render(request);
  std::vector<std::filesystem::path> inputs = parts;
  inputs.insert(inputs.end(), job.file.inputs.begin(), job.file.inputs.end());
  check_outputs(checked, inputs);
  check_sensor_stage(job, outputs.exr, outputs.png);
  if (checkpoint_key(job.file.content_hash, job.settings) != merged.header.key)
    throw Error(fmt::format("the scene {} is not the one the parts were rendered from (it changed since)",
                            request.source.label()));
  // The first-hit AOVs are traced again through pixel centres: the scene is loaded, not rendered.
  observer.on_phase(RenderPhase::writing);
  const Renderer renderer(job.file.scene, job.settings);
  if (options.denoise && !job.settings.features)
    throw Error("--denoise: the parts were rendered without --features; render them with --features");
  out.render.image = output_image(renderer, merged.film, job.file, options, observer);
  out.render.film_samples = merged.film.total_samples();
  write_render_outputs(renderer, out.render.image, job.file, outputs.exr, outputs.png, options.preview);
  out.render.sensor = sense(job.file, job.settings, out.render.image, outputs, observer);
  out.header = std::move(merged.header);
  out.missing = std::move(merged.missing);
  out.unused = std::move(merged.unused);
  out.render.total_seconds = seconds_since(t0);
  return out;
}

}  // namespace sylva

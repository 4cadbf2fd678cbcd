#pragma once
// The one render call: a scene in, its outputs out (docs/design.md §2).
//
//   render_scene(source, options, observer) → RenderResult
//
// loads the scene (a file, TOML text or the embedded default) with the caller's overrides, checks
// every output before any work, builds the BVH, renders in a session that checkpoints and resumes
// (render/session.h), and writes the EXR with its header, the PNG preview and the label sidecar,
// each atomically; it returns the film's channels in memory. A chunk of a split render
// (`options.chunk`) is written as a partial file instead (render/chunk.h). Every front end calls
// it: `sylva render` in all its modes, `sylva merge` (merge_parts), sylva-mpi (its film made over
// the ranks: RenderSeams::film_source) and the golden harness (load_render once, render_loaded for
// each of its images).
//
// The observer carries progress and messages out, and cancellation in: a front end never reaches
// into the renderer, and signal handling stays at the program's edge (the CLI switches its
// handlers on the phases it is told of).

#include "core/progress.h"
#include "pipeline/outputs.h"
#include "pipeline/scene_request.h"
#include "render/chunk.h"
#include "render/testing/faults.h"

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

enum class RenderPhase {
  loading,    // reading the scene and building its BVH: nothing has been written
  rendering,  // cancelling now keeps every finished sample (a checkpoint is written)
  writing,    // the outputs, from a film already saved as the checkpoint
};

class RenderObserver {
 public:
  RenderObserver() = default;
  RenderObserver(const RenderObserver&) = delete;
  RenderObserver& operator=(const RenderObserver&) = delete;
  virtual ~RenderObserver() = default;

  // The call enters `phase` (in the order above).
  virtual void on_phase(RenderPhase /*phase*/) {}
  // A line for a person: species-file warnings, the scene's statistics, a resumption.
  virtual void on_message(const std::string& /*text*/) {}
  // Something went wrong that the render survives (a periodic checkpoint could not be written).
  virtual void on_warning(const std::string& text) { on_message(text); }
  // Samples done and left, every 250 ms while rendering and at the end of each round.
  virtual void on_progress(const ProgressReport& /*report*/) {}
  // The flag that cancels the render once set; polled every 50 ms, so a signal handler may set it.
  virtual const std::atomic<bool>& cancel_flag() const { return cancel_; }
  // Cancels through the default flag (from any thread).
  void cancel() { cancel_.store(true); }

 private:
  std::atomic<bool> cancel_{false};
};

// The seams of a render, for harnesses and tests; a plain render leaves them empty.
struct RenderSeams {
  std::function<void(Scene&)> modify_scene;              // after loading, before the BVH is built
  std::function<void(RenderSettings&)> adjust_settings;  // after the request's overrides
  TransportFaults faults;                                // render/testing/faults.h (in-memory renders)
  std::optional<BvhBuild> bvh;                           // default: bvh_build_for(settings)
  std::optional<EmbreeIsa> isa;                          // replaces the settings' (the golden suite's AVX2)
  // Makes the whole film in place of this process's session, from the renderer of the loaded scene
  // (sylva-mpi: chunks over its ranks, assembled in order). The outputs are written from it.
  std::function<Film(Renderer&, RenderObserver&)> film_source;
};

struct RenderCallOptions {
  RenderRequest request;      // the scene source and the overrides of its settings
  std::filesystem::path exr;  // empty: the scene's [output] exr (and then nothing, if it has none)
  std::filesystem::path png;  // empty: the scene's [output] png (never for a chunk)
  bool require_exr = false;   // an error when no EXR is named at all (the CLI's case)
  PreviewOverrides preview;   // the preview's view and exposure
  bool progress_bar = false;  // progress on stderr: a bar on a terminal, else periodic lines (core/progress.h)
  bool resume = false;        // continue from the EXR's checkpoint
  double checkpoint_minutes = 10.0;
  bool memory_check = true;       // refuse a render that needs more memory than is available
  std::string chunk;              // "i/N": render one chunk to the partial file `exr` (render/chunk.h)
  std::string split = "samples";  // how a chunk splits the work: samples or tiles
  // Denoise the finished image (denoise/denoise_image.h; implies the features): the EXR and the
  // preview get the denoised beauty, the noisy one kept as noisy.<C>. Not for a chunk: give it to
  // merge_parts.
  bool denoise = false;
  RenderSeams seams;
};

enum class RenderStatus {
  finished,             // every output written
  interrupted,          // cancelled while rendering: the checkpoint holds the samples (not for chunks)
  interrupted_writing,  // cancelled while writing: the finished film is kept in the checkpoint
};

struct RenderResult {
  RenderStatus status = RenderStatus::finished;
  Image image;                   // the film's channels with the render's header (empty for a chunk)
  Image sensor;                  // the scene's [sensor] applied to `image` (pipeline/sensor_stage.h), else empty
  RenderStats stats;             // this call's rendering (seconds: rendering only)
  OutputPaths outputs;           // the files (to be) written; the checkpoint when one is kept
  uint64_t resumed_samples = 0;  // samples the resumed checkpoint held
  uint64_t film_samples = 0;     // samples in the film (in the checkpoint when interrupted)
  double load_seconds = 0;       // scene loading, overrides applied
  double total_seconds = 0;      // the whole call
};

// A scene loaded as `options` ask (overrides, seams), its outputs resolved and checked, and its BVH
// built: what render_scene renders. A caller that renders one scene several times (the golden
// harness: a check and a determinism image) loads it once.
struct LoadedScene {
  RenderJob job;
  OutputPaths outputs;
  std::unique_ptr<const EmbreeScene> embree;
  double load_seconds = 0;
};
LoadedScene load_render(const RenderCallOptions& options, RenderObserver& observer);

// Renders a loaded scene as `options` ask (their outputs and mode; the scene part of the request
// was applied by load_render). `per_render` may change this render's settings (spp, seed).
RenderResult render_loaded(const LoadedScene& loaded, const RenderCallOptions& options, RenderObserver& observer,
                           const std::function<void(RenderSettings&)>& per_render = {});

// Renders `source` as `options` ask (options.request.source is replaced by `source`). Throws
// ParseError / sylva::Error for bad input, before any work where it can be known then; an output
// that cannot be written after rendering keeps the samples in the checkpoint, and the error says so.
RenderResult render_scene(const SceneSource& source, RenderCallOptions options, RenderObserver& observer);
// The same with the source in options.request.source.
RenderResult render_scene(const RenderCallOptions& options, RenderObserver& observer);

// The frames FIRST..LAST (inclusive) of the trees' wind animation at `fps` (wind time = frame /
// fps), one render_scene call each, to OUT.NNNN.exr (and .png). Frames whose outputs exist are
// skipped (outputs are written atomically, so an existing file is a complete one); a frame's
// checkpoint is resumed with options.resume. Stops at the first frame not finished.
struct FrameRange {
  int first = 0;
  int last = 0;
  double fps = 24.0;
};
// "FIRST:LAST" with 0 <= FIRST <= LAST <= 9999999; throws sylva::Error naming --frames.
FrameRange parse_frames(const std::string& text, double fps);
struct FramesResult {
  RenderResult last;  // of the last frame rendered (status: why it stopped)
  int rendered = 0;
  int skipped = 0;
};
FramesResult render_frames(const RenderCallOptions& options, const FrameRange& frames, RenderObserver& observer);
// OUT.exr → OUT.0007.exr (at least four digits); an empty path stays empty.
std::filesystem::path frame_path(const std::filesystem::path& path, int frame);

// The partial files of a split render (`options.chunk`) → the outputs of the whole render,
// bit-identical to a single-process render (render/chunk.h). With `allow_missing`, chunks may be
// missing (a preview). The scene is loaded again (and checked against the parts' scene hash).
struct MergeResult {
  RenderResult render;
  PartialHeader header;      // the parts' common header
  std::vector<int> missing;  // chunk indices not given (only with allow_missing)
  std::vector<int> unused;   // sample chunks given but not merged: after a missing one
};
MergeResult merge_parts(const std::vector<std::filesystem::path>& parts, bool allow_missing,
                        const RenderCallOptions& options, RenderObserver& observer);

}  // namespace sylva

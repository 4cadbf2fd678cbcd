#pragma once
// `sylva study STUDY.toml`: renders a study's frames (pipeline/study_design.h) with the render call
// (pipeline/render_call.h) and writes its manifest (docs/studies.md).
//
// Output folder: frames/<id>.exr with its label sidecar frames/<id>.json (and frames/<id>.png),
// manifest.csv and manifest.json — every frame of the study with its factor values, overrides and
// outputs, the same bytes whichever frames this process rendered, so the shards of a study and a
// resumed run write the manifest one run would. A frame is finished when its EXR and sidecar (and
// preview) exist — each is written atomically — and is then skipped; a frame whose inputs changed
// has another id, so it is rendered anew and never mixed with the old one. The trees of the base
// scene are generated once per process and copied into every frame that uses them (TreeMemo), so
// frames varying sun, camera, targets or anything but the vegetation skip tree generation.

#include "pipeline/render_call.h"
#include "pipeline/study_design.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

struct StudyRunOptions {
  std::filesystem::path output_dir;  // empty: the study's `output`
  int shard_index = 0;               // this process renders frames with index % count == shard_index
  int shard_count = 1;
  int threads = 0;         // 0: all
  bool plan_only = false;  // write the manifest, render nothing
  // When set, the frames this process renders are those it hands out (indices into the plan, in
  // any order) until it returns none, in place of the shard's: sylva-mpi's ranks ask rank 0.
  std::function<std::optional<size_t>()> next_frame;
};

// "i/N" with 0 <= i < N <= 1e6; throws sylva::Error naming --shard.
std::pair<int, int> parse_shard(const std::string& text);

// One line of progress: after each frame of this process's share (rendered or skipped).
struct StudyProgress {
  size_t done = 0, total = 0;  // of this shard's frames
  size_t rendered = 0, skipped = 0;
  double seconds = 0;            // since the study started
  double seconds_per_frame = 0;  // rendered frames' mean (0 before the first)
  double eta_seconds = 0;
  uint64_t max_rss_bytes = 0;  // of this process so far
  std::string frame_id;
};
// "study: 12/200 frames (9 rendered, 3 skipped), 4.20 s/frame, ETA 13m10s, max RSS 512 MiB".
std::string progress_line(const StudyProgress& p);

struct StudyResult {
  std::vector<StudyFrame> frames;  // the whole plan
  std::filesystem::path output_dir, manifest_csv, manifest_json;
  size_t rendered = 0, skipped = 0;
  RenderStatus status = RenderStatus::finished;  // not finished: cancelled in the frame `stopped_at`
  std::string stopped_at;
  double seconds = 0;
  uint64_t max_rss_bytes = 0;
  uint64_t trees_generated = 0, trees_reused = 0;  // TreeMemo's counts
};

// Plans the study, writes its manifest, then renders this shard's unfinished frames in order (or
// those `next_frame` hands out). Once every frame of the study is finished, writes its coco.json.
// `on_progress` is called after each frame. Throws ParseError / Error for bad input.
StudyResult run_study(const StudySpec& spec, const StudyRunOptions& options, RenderObserver& observer,
                      const std::function<void(const StudyProgress&)>& on_progress = {});

// The manifest of `frames` (the outputs relative to the output folder), as CSV and as JSON.
std::string manifest_csv(const StudySpec& spec, const std::vector<StudyFrame>& frames);
std::string manifest_json(const StudySpec& spec, const std::vector<StudyFrame>& frames, const SceneFile& base);

}  // namespace sylva

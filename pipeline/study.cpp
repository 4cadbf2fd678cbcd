#include "pipeline/study.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipeline/study_annotations.h"
#include "render/session.h"
#include "scenes/sections/scene_builder.h"
#include "scenes/sidecar.h"
#include "scenes/tree_variants.h"

#include <fmt/core.h>

#include <sys/resource.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <ostream>

namespace sylva {

namespace {

using StudyClock = std::chrono::steady_clock;

uint64_t max_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<uint64_t>(usage.ru_maxrss) * 1024u;  // Linux: kibibytes
}

struct FramePaths {
  std::filesystem::path exr, sidecar, png, coco, yolo, voc;
};

FramePaths frame_paths(const StudySpec& spec, const std::filesystem::path& dir, const StudyFrame& frame) {
  FramePaths p;
  const std::filesystem::path stem = dir / "frames" / frame.id;
  p.exr = stem.string() + ".exr";
  p.sidecar = sidecar_path(p.exr);
  if (spec.png) p.png = stem.string() + ".png";
  p.coco = stem.string() + ".coco.json";
  p.yolo = stem.string() + ".txt";
  p.voc = stem.string() + ".xml";
  return p;
}

// Every output of the frame; the annotations are written last.
bool frame_finished(const FramePaths& p) {
  for (const std::filesystem::path* f : {&p.exr, &p.sidecar, &p.png, &p.coco, &p.yolo, &p.voc})
    if (!f->empty() && !std::filesystem::exists(*f)) return false;
  return true;
}

// The YOLO class list: the labels of the base scene's targets and every label a factor gives a
// target (`set = "targets.NAME.label"`), by class id.
std::vector<std::string> study_classes(const StudySpec& spec, const SceneFile& base) {
  std::map<uint32_t, std::string> classes;
  for (const TargetInfo& t : base.targets) classes[t.class_id] = base.scene.class_names.at(t.class_id);
  for (const StudyFactor& f : spec.factors) {
    if (f.set.size() < 6 || f.set.compare(f.set.size() - 6, 6, ".label") != 0) continue;
    for (const std::string& v : f.values)
      if (v.size() >= 2 && v.front() == '"' && v.back() == '"') {
        const std::string name = v.substr(1, v.size() - 2);
        classes[class_id_of(name)] = name;
      }
  }
  std::vector<std::string> out;
  for (const auto& [id, name] : classes) out.push_back(name);
  return out;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  write_file_atomic(path, [&](std::ostream& out) { out << text; });
}

// Renders a frame and writes its annotations; returns the render's result.
RenderResult render_frame(const RenderCallOptions& call, const StudyFrame& frame, const FramePaths& paths,
                          const std::vector<std::string>& classes, int threads, RenderObserver& observer) {
  const LoadedScene loaded = load_render(call, observer);
  RenderResult r = render_loaded(loaded, call, observer);
  if (r.status != RenderStatus::finished) return r;
  FrameAnnotationInput in;
  in.frame_index = frame.index;
  in.frame_id = frame.id;
  in.image_file = (std::filesystem::path("frames") / paths.exr.filename()).string();
  in.file = &loaded.job.file;
  in.image = &r.image;
  in.targets = annotate_targets(loaded.job.file, r.image, threads);
  write_text(paths.voc, frame_voc(in));
  write_text(paths.yolo, frame_yolo(in, classes));
  write_text(paths.coco, frame_coco(in));
  return r;
}

// The study's COCO file and YOLO class list, once every frame of the study is finished.
void write_study_annotations(const StudySpec& spec, const StudyResult& result,
                             const std::vector<std::string>& classes) {
  std::vector<std::filesystem::path> files;
  for (const StudyFrame& frame : result.frames) {
    const FramePaths p = frame_paths(spec, result.output_dir, frame);
    if (!frame_finished(p)) return;
    files.push_back(p.coco);
  }
  std::string names;
  for (const std::string& c : classes) names += c + "\n";
  write_text(result.output_dir / "yolo_classes.txt", names);
  write_text(result.output_dir / "coco.json", study_coco(files, spec.file.filename().string()));
}

// A CSV field: quoted when it holds a comma, quote or line break (RFC 4180).
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string duration_text(double seconds) {
  const auto s = static_cast<int64_t>(std::llround(std::max(0.0, seconds)));
  if (s >= 3600) return fmt::format("{}h{:02}m", s / 3600, (s / 60) % 60);
  if (s >= 60) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}s", s);
}

const char* design_name(StudyDesign d) {
  switch (d) {
    case StudyDesign::grid:
      return "grid";
    case StudyDesign::list:
      return "list";
    case StudyDesign::latin_hypercube:
      return "latin_hypercube";
  }
  return "";
}

// The frame's render: the base scene with the frame's overrides, to its outputs.
RenderCallOptions frame_call(const StudySpec& spec, const StudyRunOptions& options, const FramePaths& paths,
                             const StudyFrame& frame, const std::shared_ptr<TreeMemo>& memo) {
  RenderCallOptions call;
  call.request.source = SceneSource::from_file(spec.scene.string());
  call.request.overrides = frame.overrides;
  call.request.threads = options.threads;
  call.request.tree_memo = memo;
  call.exr = paths.exr;
  call.png = paths.png;
  call.require_exr = true;
  call.resume = std::filesystem::exists(checkpoint_path_for(paths.exr));
  return call;
}

}  // namespace

std::pair<int, int> parse_shard(const std::string& text) {
  const size_t slash = text.find('/');
  int i = -1, n = 0;
  const auto parse = [](std::string_view s, int& v) {
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return !s.empty() && ec == std::errc() && ptr == s.data() + s.size();
  };
  const std::string_view all(text);
  if (slash == std::string::npos || !parse(all.substr(0, slash), i) || !parse(all.substr(slash + 1), n) || i < 0 ||
      n < 1 || n > 1'000'000 || i >= n)
    throw Error(fmt::format("--shard: expected i/N with 0 <= i < N, e.g. 0/4, not '{}'", text));
  return {i, n};
}

std::string progress_line(const StudyProgress& p) {
  std::string line =
      fmt::format("study: {}/{} frames ({} rendered, {} skipped)", p.done, p.total, p.rendered, p.skipped);
  if (p.rendered > 0)
    line += fmt::format(", {:.2f} s/frame, ETA {}", p.seconds_per_frame, duration_text(p.eta_seconds));
  return line + fmt::format(", max RSS {} MiB", p.max_rss_bytes >> 20);
}

std::string manifest_csv(const StudySpec& spec, const std::vector<StudyFrame>& frames) {
  std::string out = "frame,id";
  for (const StudyFactor& f : spec.factors) {
    out += ',';
    out += csv_field(f.name);
  }
  out += ",exr,sidecar,png,coco,yolo,voc,overrides\n";
  for (const StudyFrame& frame : frames) {
    const FramePaths p = frame_paths(spec, "", frame);
    out += fmt::format("{},{}", frame.index, frame.id);
    for (const std::string& v : frame.values) {
      out += ',';
      out += csv_field(v);
    }
    std::string overrides;
    for (const std::string& o : frame.overrides)
      overrides += fmt::format("{}--set '{}'", overrides.empty() ? "" : " ", o);
    out += fmt::format(",{},{},{},{},{},{},{}\n", p.exr.string(), p.sidecar.string(), p.png.string(), p.coco.string(),
                       p.yolo.string(), p.voc.string(), csv_field(overrides));
  }
  return out;
}

std::string manifest_json(const StudySpec& spec, const std::vector<StudyFrame>& frames, const SceneFile& base) {
  std::string out = "{\n  \"format\": \"sylva-study\",\n  \"version\": 1,\n";
  out += fmt::format("  \"study\": {},\n  \"scene\": {},\n  \"scene_hash\": {},\n  \"design\": \"{}\",\n",
                     json_string(spec.file.filename().string()), json_string(spec.scene.filename().string()),
                     json_string(base.content_hash), design_name(spec.design));
  out += "  \"factors\": [";
  for (size_t f = 0; f < spec.factors.size(); ++f)
    out += fmt::format("{}\n    {{\"name\": {}, \"set\": {}}}", f ? "," : "", json_string(spec.factors[f].name),
                       json_string(spec.factors[f].set));
  out += "\n  ],\n  \"frames\": [";
  for (const StudyFrame& frame : frames) {
    const FramePaths p = frame_paths(spec, "", frame);
    std::string values, overrides;
    for (size_t f = 0; f < spec.factors.size(); ++f)
      values += fmt::format("{}{}: {}", f ? ", " : "", json_string(spec.factors[f].name), json_string(frame.values[f]));
    for (const std::string& o : frame.overrides)
      overrides += fmt::format("{}{}", overrides.empty() ? "" : ", ", json_string(o));
    out += fmt::format(
        "{}\n    {{\"frame\": {}, \"id\": \"{}\", \"values\": {{{}}}, \"overrides\": [{}], \"exr\": {}, "
        "\"sidecar\": {}, \"png\": {}, \"coco\": {}, \"yolo\": {}, \"voc\": {}}}",
        frame.index ? "," : "", frame.index, frame.id, values, overrides, json_string(p.exr.string()),
        json_string(p.sidecar.string()), p.png.empty() ? "null" : json_string(p.png.string()),
        json_string(p.coco.string()), json_string(p.yolo.string()), json_string(p.voc.string()));
  }
  return out + "\n  ]\n}\n";
}

StudyResult run_study(const StudySpec& spec, const StudyRunOptions& options, RenderObserver& observer,
                      const std::function<void(const StudyProgress&)>& on_progress) {
  const auto t0 = StudyClock::now();
  StudyResult result;
  result.output_dir = options.output_dir.empty() ? spec.output_dir : options.output_dir;
  const auto memo = std::make_shared<TreeMemo>();
  SceneOptions base_options;
  base_options.overrides = spec.set;
  base_options.tree_memo = memo;
  const SceneFile base = load_scene_file(spec.scene, base_options);
  result.frames = plan_study(spec, base);
  const std::vector<std::string> classes = study_classes(spec, base);
  std::filesystem::create_directories(result.output_dir / "frames");
  result.manifest_csv = result.output_dir / "manifest.csv";
  result.manifest_json = result.output_dir / "manifest.json";
  const std::string csv = manifest_csv(spec, result.frames), json = manifest_json(spec, result.frames, base);
  write_file_atomic(result.manifest_csv, [&](std::ostream& out) { out << csv; });
  write_file_atomic(result.manifest_json, [&](std::ostream& out) { out << json; });
  const auto mine = [&](size_t index) {
    return index % options.shard_count == static_cast<size_t>(options.shard_index);
  };
  StudyProgress progress;
  for (const StudyFrame& f : result.frames) progress.total += options.next_frame || mine(f.index);
  // This process's frames: its shard's in order, or those next_frame hands out.
  size_t cursor = 0;
  const auto take = [&]() -> const StudyFrame* {
    if (options.plan_only) return nullptr;
    if (options.next_frame) {
      const std::optional<size_t> i = options.next_frame();
      return i && *i < result.frames.size() ? &result.frames[*i] : nullptr;
    }
    while (cursor < result.frames.size() && !mine(cursor)) ++cursor;
    return cursor < result.frames.size() ? &result.frames[cursor++] : nullptr;
  };
  double render_seconds = 0;
  for (const StudyFrame* next = take(); next != nullptr; next = take()) {
    const StudyFrame& frame = *next;
    const FramePaths paths = frame_paths(spec, result.output_dir, frame);
    const auto start = StudyClock::now();
    if (frame_finished(paths)) {
      ++result.skipped;
    } else {
      memo->next_scene();
      const RenderResult r =
          render_frame(frame_call(spec, options, paths, frame, memo), frame, paths, classes, options.threads, observer);
      if (r.status != RenderStatus::finished) {
        result.status = r.status;
        result.stopped_at = frame.id;
        break;
      }
      ++result.rendered;
      render_seconds += std::chrono::duration<double>(StudyClock::now() - start).count();
    }
    progress.done = result.rendered + result.skipped;
    progress.rendered = result.rendered;
    progress.skipped = result.skipped;
    progress.seconds = std::chrono::duration<double>(StudyClock::now() - t0).count();
    progress.seconds_per_frame = result.rendered ? render_seconds / static_cast<double>(result.rendered) : 0;
    progress.eta_seconds = progress.seconds_per_frame * static_cast<double>(progress.total - progress.done);
    progress.max_rss_bytes = max_rss_bytes();
    progress.frame_id = frame.id;
    if (on_progress) on_progress(progress);
  }
  if (result.status == RenderStatus::finished && !options.plan_only) write_study_annotations(spec, result, classes);
  result.seconds = std::chrono::duration<double>(StudyClock::now() - t0).count();
  result.max_rss_bytes = max_rss_bytes();
  result.trees_generated = memo->generated();
  result.trees_reused = memo->reused();
  return result;
}

}  // namespace sylva

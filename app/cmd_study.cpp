// `sylva study STUDY.toml`: a detection study — a base scene and factors combined into frames, each
// rendered with its label sidecar, one manifest for all (pipeline/study.h, docs/studies.md).
// Resumable (finished frames are skipped) and shardable (`--shard i/N`); signals stop it cleanly
// with the current frame's checkpoint, which the next run resumes.

#include "app/cli_observer.h"
#include "app/commands.h"
#include "core/error.h"
#include "pipeline/study.h"

#include <fmt/core.h>

#include <unistd.h>

#include <cstdio>
#include <tuple>

namespace sylva {

namespace {

struct StudyCommandOptions {
  std::string study;
  std::string output;
  std::string shard = "0/1";
  int threads = 0;
  bool plan_only = false;
  bool quiet = false;
};

int run_study_command(const StudyCommandOptions& opt) {
  const InterruptHandlers interrupt_handlers(InterruptHandlers::OnSignal::exit);
  CliObserver observer(true);  // per-frame render messages are too many: the study prints its own line
  const StudySpec spec = load_study(opt.study);
  StudyRunOptions run;
  run.output_dir = opt.output;
  std::tie(run.shard_index, run.shard_count) = parse_shard(opt.shard);
  run.threads = opt.threads;
  run.plan_only = opt.plan_only;
  const bool terminal = isatty(fileno(stderr)) != 0;
  const StudyResult r = run_study(spec, run, observer, [&](const StudyProgress& p) {
    if (!opt.quiet) fmt::print(stderr, "{}{}{}", terminal ? "\r" : "", progress_line(p), terminal ? "\x1b[K" : "\n");
  });
  if (!opt.quiet && terminal) fmt::print(stderr, "\n");
  if (r.status != RenderStatus::finished) {
    fmt::print(stderr, "study interrupted in frame {}: run the same command again to resume\n", r.stopped_at);
    return 130;
  }
  if (!opt.quiet)
    fmt::print(stderr,
               "study: {} frames planned, {} rendered, {} skipped in {:.1f} s; trees generated {}, reused {}; max RSS "
               "{} MiB; manifest {}\n",
               r.frames.size(), r.rendered, r.skipped, r.seconds, r.trees_generated, r.trees_reused,
               r.max_rss_bytes >> 20, r.manifest_json.string());
  return 0;
}

}  // namespace

CommandRun add_study_command(CLI::App& parent) {
  auto opt = std::make_shared<StudyCommandOptions>();
  CLI::App* cmd =
      parent.add_subcommand("study", "Render a detection study: a base scene varied by factors, with a manifest");
  cmd->add_option("study", opt->study, "Study file (TOML; docs/studies.md)")->required();
  cmd->add_option("-o,--output", opt->output, "Output folder (default: the study's [study] output)");
  cmd->add_option("--shard", opt->shard, "Render only the frames i, i + N, i + 2N, ... (0 <= i < N)");
  cmd->add_option("--threads", opt->threads, "Worker threads (0 = all)")->check(CLI::Range(0, 4096));
  cmd->add_flag("--plan", opt->plan_only, "Write the manifest only, render nothing");
  cmd->add_flag("-q,--quiet", opt->quiet, "No progress line or summary");
  return [opt] { return run_study_command(*opt); };
}

}  // namespace sylva

// `sylva merge`: the partial files of a split render (`sylva render --chunk i/N`) → the EXR and PNG
// of the whole render, bit-identical to a single-process render (render/chunk.h). The first-hit
// AOVs are traced again through pixel centres, so the scene is loaded (and checked against the
// parts' scene hash) but not rendered.

#include "app/cli_observer.h"
#include "app/commands.h"
#include "pipeline/render_call.h"

#include <fmt/core.h>

namespace sylva {

namespace {

struct MergeOptions {
  std::vector<std::string> parts;
  std::string exr;
  std::string png;
  bool partial = false;
  int threads = 0;
  bool quiet = false;
  bool denoise = false;
};

std::string list(const std::vector<int>& v) {
  std::string s;
  for (const int i : v) s += (s.empty() ? "" : ", ") + std::to_string(i);
  return s;
}

int run_merge(const MergeOptions& opt) {
  CliObserver observer(opt.quiet);
  RenderCallOptions call;
  call.exr = opt.exr;
  call.png = opt.png;
  call.request.threads = opt.threads;
  call.denoise = opt.denoise;
  std::vector<std::filesystem::path> files(opt.parts.begin(), opt.parts.end());
  const MergeResult merged = merge_parts(files, opt.partial, call, observer);
  const int n = merged.header.chunk.count;
  if (!merged.missing.empty())
    fmt::print(stderr, "partial merge: chunks {} of {} missing{}\n", list(merged.missing), n,
               merged.unused.empty()
                   ? std::string()
                   : fmt::format("; sample chunks {} not used (they follow a missing one)", list(merged.unused)));
  if (!opt.quiet)
    fmt::print(stderr, "merged {} of {} chunks (split by {}) into {}{} in {:.2f} s\n",
               n - static_cast<int>(merged.missing.size() + merged.unused.size()), n,
               to_string(merged.header.chunk.split), opt.exr, opt.png.empty() ? "" : " and " + opt.png,
               merged.render.total_seconds);
  return 0;
}

}  // namespace

CommandRun add_merge_command(CLI::App& parent) {
  auto opt = std::make_shared<MergeOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "merge", "Merge the partial files of a split render (sylva render --chunk) into its EXR and PNG");
  cmd->add_option("parts", opt->parts, "Partial files, one per chunk, in any order")->required();
  cmd->add_option("-o,--output", opt->exr, "Output EXR (written atomically)")->required();
  cmd->add_option("--png", opt->png, "PNG preview of the visible band (OCIO display transform)");
  cmd->add_flag("--partial", opt->partial, "Merge the chunks given even if some are missing (a preview)");
  cmd->add_option("--threads", opt->threads, "Worker threads (0 = all)")->check(CLI::Range(0, 4096));
  cmd->add_flag("--denoise", opt->denoise, "Denoise the merged image (the parts rendered with --features)");
  cmd->add_flag("-q,--quiet", opt->quiet, "No summary");
  return [opt] { return run_merge(*opt); };
}

}  // namespace sylva

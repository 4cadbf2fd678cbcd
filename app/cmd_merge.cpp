// `sylva merge`: the partial files of a split render (`sylva render --chunk i/N`) → the EXR and PNG
// of the whole render, bit-identical to a single-process render (render/chunk.h). The first-hit
// AOVs are traced again through pixel centres, so the scene is loaded (and checked against the
// parts' scene hash) but not rendered.

#include "app/commands.h"
#include "app/render_job.h"
#include "core/error.h"
#include "core/output_paths.h"
#include "render/chunk.h"
#include "render/session.h"
#include "scenes/sidecar.h"

#include <fmt/core.h>

#include <chrono>

namespace sylva {

namespace {

struct MergeOptions {
  std::vector<std::string> parts;
  std::string exr;
  std::string png;
  bool partial = false;
  int threads = 0;
  bool quiet = false;
};

std::string list(const std::vector<int>& v) {
  std::string s;
  for (const int i : v) s += (s.empty() ? "" : ", ") + std::to_string(i);
  return s;
}

int run_merge(const MergeOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::filesystem::path> files(opt.parts.begin(), opt.parts.end());
  const std::vector<OutputFile> outputs{
      {"-o", opt.exr},
      {"--png", opt.png},
      {"label sidecar", opt.exr.empty() ? std::filesystem::path() : sidecar_path(opt.exr)}};
  check_outputs(outputs, files);
  const MergedParts merged = merge_partials(files, opt.partial);
  RenderRequest request = request_from_job(merged.header.job, merged.header.spp);
  request.threads = opt.threads;
  const RenderJob job = prepare_render(request);
  std::vector<std::filesystem::path> inputs = files;
  inputs.insert(inputs.end(), job.file.inputs.begin(), job.file.inputs.end());
  check_outputs(outputs, inputs);
  if (checkpoint_key(job.file.content_hash, job.settings) != merged.header.key)
    throw Error(fmt::format("the scene {} is not the one the parts were rendered from (it changed since)",
                            request.scene.empty() ? "<default scene>" : request.scene));
  const Renderer renderer(job.file.scene, job.settings);
  write_render_outputs(renderer, merged.film, job, opt.exr, opt.png, {});
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
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
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
  cmd->add_flag("-q,--quiet", opt->quiet, "No summary");
  return [opt] { return run_merge(*opt); };
}

}  // namespace sylva

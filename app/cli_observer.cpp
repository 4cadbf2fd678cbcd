#include "app/cli_observer.h"

#include "app/commands.h"
#include "core/memory.h"

#include <fmt/core.h>

#include <algorithm>

namespace sylva {

void CliObserver::on_phase(RenderPhase phase) {
  InterruptHandlers::set(phase == RenderPhase::loading ? InterruptHandlers::OnSignal::exit
                                                       : InterruptHandlers::OnSignal::set_flag);
}

void CliObserver::on_message(const std::string& text) {
  if (!quiet_) fmt::print(stderr, "{}\n", text);
}

void CliObserver::on_warning(const std::string& text) { fmt::print(stderr, "\n{}\n", text); }

void add_request_options(CLI::App* cmd, RenderRequest& req) {
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
  cmd->add_option("--noise-threshold", req.noise_threshold,
                  "Adaptive sampling: the relative standard error each pixel should reach, e.g. 0.02 "
                  "(--spp is then the most a pixel takes; docs/sampling.md)")
      ->check(CLI::Range(0.0, 0.999));
  cmd->add_option("--noise-channels", req.noise_channels,
                  "Comma-separated channels the noise threshold applies to (default: every band channel), e.g. R,G,B");
  cmd->add_option("--time-limit", req.time_limit_s,
                  "Stop after this many seconds of rendering and write the image (samples spread over every pixel)")
      ->check(CLI::Range(0.0, 1e9));
  add_set_option(cmd, req.overrides);
}

void add_set_option(CLI::App* cmd, std::vector<std::string>& overrides) {
  cmd->add_option("--set", overrides,
                  "Override a key of the scene file: SECTION.KEY=VALUE, e.g. sun.elevation=10, "
                  "camera.position=[0,-30,2] or trees[0].seed=7 (repeatable)")
      ->allow_extra_args(false);  // one value per --set, so a scene file after it stays positional
}

int report_interrupted(const RenderResult& r) {
  if (r.status == RenderStatus::interrupted_writing)
    fmt::print(stderr, "\ninterrupted while writing the outputs: {} kept; run the same command with --resume\n",
               r.outputs.checkpoint.string());
  else if (r.outputs.checkpoint.empty())
    fmt::print(stderr, "\ninterrupted: {} not written\n", r.outputs.exr.string());
  else
    fmt::print(stderr,
               "\ninterrupted: checkpoint with {} samples written to {}; continue with the same command and --resume\n",
               r.film_samples, r.outputs.checkpoint.string());
  return 130;
}

std::string summary_line(const std::string& what, const RenderResult& r) {
  const RenderStats& total = r.stats;
  const ResidentMemory memory = resident_memory();
  return fmt::format(
      "wrote {}: {} samples in {:.2f} s render ({:.2f} s total): {:.3f} M samples/s, {:.3f} M rays/s "
      "({:.2f} CPU-s: {:.3f} M rays per CPU-second); {:.0f} MiB resident, {:.0f} MiB of it in huge pages",
      what, total.samples, total.seconds, r.total_seconds, total.samples / std::max(1e-9, total.seconds) / 1e6,
      total.rays / std::max(1e-9, total.seconds) / 1e6, total.cpu_seconds,
      total.rays / std::max(1e-9, total.cpu_seconds) / 1e6, memory.bytes / 1048576.0,
      memory.huge_page_bytes / 1048576.0);
}

}  // namespace sylva

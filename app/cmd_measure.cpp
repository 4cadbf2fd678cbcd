// `sylva measure`: the plot sensor (docs/radiometry.md, "Plot sensor"): the BRF (or mean
// radiance) of a scene's [plot] for its view directions, and the plot's flux budget, as CSV.

#include "app/cli_observer.h"
#include "app/commands.h"
#include "pipeline/measure.h"

#include <fmt/core.h>

#include <memory>

namespace sylva {

CommandRun add_measure_command(CLI::App& parent) {
  auto opt = std::make_shared<MeasureCallOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "measure",
      "Plot sensor: the BRF (or mean radiance) of the scene's [plot] per view direction and its flux budget, as CSV "
      "with standard errors (docs/radiometry.md)");
  RenderRequest& req = opt->request;
  cmd->add_option("scene", req.source.file, "Scene file (TOML) with a [plot] section")->required();
  cmd->add_option("--brf", opt->brf, "Output CSV: per view direction, each band channel's mean and standard error");
  cmd->add_option("--flux", opt->flux, "Output CSV: per band channel, the flux fractions and standard errors");
  cmd->add_option("--samples", opt->samples, "Rays per view direction (default: [plot] samples)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--flux-samples", opt->flux_samples, "Light paths of the flux budget (default: [plot] flux_samples)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--threads", req.threads, "Worker threads (0 = all)")->check(CLI::Range(0, 4096));
  cmd->add_option("--seed", req.seed, "Random seed")->check(kUint64 & CLI::Range(int64_t{0}, INT64_MAX));
  cmd->add_option("--bands", req.bands, "Comma-separated bands, e.g. S2A_B4,S2A_B8 (default: the scene's)");
  cmd->add_option("--max-depth", req.max_depth, "Maximum path depth")->check(CLI::Range(1, 1024));
  cmd->add_option("--quantity", req.quantity, "BRF columns as reflectance (factor, the default) or radiance")
      ->check(CLI::IsMember({"radiance", "reflectance"}));
  cmd->add_option("--isa", req.isa, "Embree's kernels, at most (as sylva render --isa; default avx2)")
      ->check(CLI::IsMember(embree_isa_names()));
  add_set_option(cmd, req.overrides);
  return [opt] {
    CliObserver observer(false);
    const MeasureResult r = measure_scene(*opt, observer);
    if (r.brf)
      fmt::print(stderr, "measure: {} views x {} rays in {:.1f} s -> {}\n", r.brf->views.size(), r.brf->samples,
                 r.brf_seconds, opt->brf.string());
    if (r.flux)
      fmt::print(stderr, "measure: flux budget of {} paths in {:.1f} s -> {}\n", r.flux->samples, r.flux_seconds,
                 opt->flux.string());
    return 0;
  };
}

}  // namespace sylva

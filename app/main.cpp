// sylva: the command-line entry point (composition root).

#include "app/commands.h"
#include "core/error.h"
#include "core/memory.h"

#include <fmt/core.h>

#include <utility>
#include <vector>

int main(int argc, char** argv) {
  sylva::use_huge_pages(argv);
  CLI::App app{"Sylva: a physically based spectral forest renderer"};
  app.require_subcommand(1);
  app.set_version_flag("--version", SYLVA_VERSION);

  std::vector<std::pair<CLI::App*, sylva::CommandRun>> commands;
  auto add = [&](sylva::CommandRun run) { commands.emplace_back(app.get_subcommands({}).back(), std::move(run)); };
  add(sylva::add_render_command(app));
  add(sylva::add_merge_command(app));
  add(sylva::add_denoise_command(app));
  add(sylva::add_compare_command(app));
  add(sylva::add_tree_command(app));
  add(sylva::add_grow_command(app));
  add(sylva::add_export_command(app));
  add(sylva::add_golden_command(app));
  add(sylva::add_bands_command(app));
  add(sylva::add_measure_command(app));
  add(sylva::add_study_command(app));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    for (auto& [sub, run] : commands)
      if (sub->parsed()) return run();
  } catch (const sylva::Error& e) {
    fmt::print(stderr, "sylva: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "sylva: internal error: {}\n", e.what());
    return 3;
  }
  return 2;
}

#pragma once
// The `sylva` subcommands. Each add_*_command registers its options on `parent` and returns the
// function that runs it once the command line has been parsed; that function returns the exit
// code and reports failures by throwing sylva::Error (main prints it and exits non-zero).

#include <CLI/CLI.hpp>

#include <functional>

namespace sylva {

using CommandRun = std::function<int()>;

CommandRun add_render_command(CLI::App& parent);
CommandRun add_compare_command(CLI::App& parent);
CommandRun add_tree_command(CLI::App& parent);
CommandRun add_export_command(CLI::App& parent);
CommandRun add_golden_command(CLI::App& parent);
CommandRun add_merge_command(CLI::App& parent);
CommandRun add_grow_command(CLI::App& parent);
CommandRun add_bands_command(CLI::App& parent);

}  // namespace sylva

#pragma once
// The `sylva` subcommands. Each add_*_command registers its options on `parent` and returns the
// function that runs it once the command line has been parsed; that function returns the exit
// code and reports failures by throwing sylva::Error (main prints it and exits non-zero).

#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string>

namespace sylva {

using CommandRun = std::function<int()>;

// For every floating-point option: a finite number (CLI11's range checks let NaN through, and
// strtod turns "1e999" into infinity).
inline const CLI::Validator kFiniteNumber(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(v)) return "expected a finite number, got '" + text + "'";
      return {};
    },
    "FINITE");

// For 64-bit unsigned options (seeds): decimal digits that fit in 64 bits (no wrap-around).
inline const CLI::Validator kUint64(
    [](std::string& text) -> std::string {
      uint64_t v = 0;
      const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
      if (text.empty() || ec != std::errc() || ptr != text.data() + text.size())
        return "expected an integer from 0 to 18446744073709551615, got '" + text + "'";
      return {};
    },
    "UINT64");

CommandRun add_render_command(CLI::App& parent);
CommandRun add_compare_command(CLI::App& parent);
CommandRun add_tree_command(CLI::App& parent);
CommandRun add_export_command(CLI::App& parent);
CommandRun add_golden_command(CLI::App& parent);
CommandRun add_merge_command(CLI::App& parent);
CommandRun add_denoise_command(CLI::App& parent);
CommandRun add_grow_command(CLI::App& parent);
CommandRun add_bands_command(CLI::App& parent);
CommandRun add_measure_command(CLI::App& parent);
CommandRun add_study_command(CLI::App& parent);

}  // namespace sylva

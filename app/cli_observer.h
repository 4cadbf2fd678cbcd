#pragma once
// What the render front ends of the command line share: the observer that prints the render
// call's messages, switches the signal handlers with its phases and cancels on a signal; the
// options every render takes; and the lines printed when a render ends.

#include "pipeline/render_call.h"
#include "render/session.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace sylva {

// Prints messages on stderr (unless quiet; warnings always). While the scene loads, SIGINT and
// SIGTERM end the process at once (nothing has been written); once rendering starts they set the
// flag that cancels the render cleanly (a checkpoint is written). Needs an InterruptHandlers alive.
class CliObserver : public RenderObserver {
 public:
  explicit CliObserver(bool quiet) : quiet_(quiet) {}
  void on_phase(RenderPhase phase) override;
  void on_message(const std::string& text) override;
  void on_warning(const std::string& text) override;
  const std::atomic<bool>& cancel_flag() const override { return InterruptHandlers::flag(); }

 private:
  bool quiet_;
};

// --spp, --res, --threads, --seed, --bands, --max-depth, --quantity, --isa and --set on `cmd`.
void add_request_options(CLI::App* cmd, RenderRequest& request);
// --set SECTION.KEY=VALUE, repeatable (SceneOptions::overrides).
void add_set_option(CLI::App* cmd, std::vector<std::string>& overrides);

// The message of a render that was cancelled (on stderr), and the exit code: 130.
int report_interrupted(const RenderResult& result);

// "wrote WHAT: N samples in … s render (… s total): rates; memory".
std::string summary_line(const std::string& what, const RenderResult& result);

}  // namespace sylva

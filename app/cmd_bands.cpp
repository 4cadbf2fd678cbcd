// `sylva bands`: every built-in band with its channels' centre wavelength, widths and source.

#include "app/commands.h"
#include "core/band.h"

#include <fmt/core.h>

#include <memory>

namespace sylva {

CommandRun add_bands_command(CLI::App& parent) {
  auto csv = std::make_shared<bool>(false);
  CLI::App* cmd = parent.add_subcommand(
      "bands",
      "List the built-in bands: per channel the centre wavelength (response-weighted mean), the full width at "
      "half maximum, the equivalent width (area / peak), in nm, and the source (docs/radiometry.md)");
  cmd->add_flag("--csv", *csv, "Comma-separated values with a header row");
  return [csv] {
    if (*csv)
      fmt::print("band,channel,centre_nm,fwhm_nm,equivalent_width_nm,source\n");
    else
      fmt::print("{:<10} {:<12} {:>9} {:>8} {:>9}  {}\n", "band", "channel", "centre", "FWHM", "eq.width", "source");
    for (const std::string& name : known_band_names()) {
      const Band b = resolve_band(name);
      for (size_t c = 0; c < b.channels.size(); ++c) {
        const ChannelSummary s = summarise_channel(b.weights[c]);
        if (*csv)
          fmt::print("{},{},{:.1f},{:.1f},{:.1f},\"{}\"\n", b.name, b.channels[c], s.centre_nm, s.fwhm_nm,
                     s.equivalent_width_nm, b.source);
        else
          fmt::print("{:<10} {:<12} {:>9.1f} {:>8.1f} {:>9.1f}  {}\n", b.name, b.channels[c], s.centre_nm, s.fwhm_nm,
                     s.equivalent_width_nm, b.source);
      }
    }
    return 0;
  };
}

}  // namespace sylva

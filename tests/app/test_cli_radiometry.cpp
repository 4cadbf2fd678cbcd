// `sylva bands` and `sylva render --quantity`: the band list and the reflectance-factor header.

#include "core/band.h"
#include "core/image.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::run_sylva;

TEST(CliBands, ListsEveryBuiltInBandWithCentreWidthAndSource) {
  const fs::path dir = fresh_dir("cli_bands");
  const auto r = run_sylva("bands --csv", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "band,channel,centre_nm,fwhm_nm,equivalent_width_nm,source");
  int rows = 0;
  bool b8 = false;
  while (std::getline(in, line)) {
    ++rows;
    if (line.rfind("S2A_B8,S2A_B8.Y,", 0) == 0) {
      b8 = true;
      const double centre = std::stod(line.substr(std::string("S2A_B8,S2A_B8.Y,").size()));
      EXPECT_NEAR(centre, 832.8, 3.0);  // ESA's stated centre
    }
  }
  EXPECT_TRUE(b8);
  // rgb's three channels + one for every other known band.
  EXPECT_EQ(rows, static_cast<int>(known_band_names().size()) + 2);
  const auto table = run_sylva("bands", dir);
  ASSERT_EQ(table.exit_code, 0);
  EXPECT_NE(table.out.find("Sentinel_2A_Spectral_Response.tsv, column B4"), std::string::npos);
}

TEST(CliRender, ReflectanceQuantityIsRecordedInTheHeader) {
  const fs::path dir = fresh_dir("cli_reflectance");
  const std::string common = " --res 16x9 --spp 2 --quiet --bands rgb,S2A_B8";
  ASSERT_EQ(run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "l.exr").string() + "'" +
                          common,
                      dir)
                .exit_code,
            0);
  const auto r = run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" + (dir / "r.exr").string() +
                               "' --quantity reflectance" + common,
                           dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image l = read_exr(dir / "l.exr"), f = read_exr(dir / "r.exr");
  EXPECT_EQ(l.attribute("sylva:quantity"), "radiance");
  EXPECT_EQ(f.attribute("sylva:quantity"), "reflectance");
  const std::string e = f.attribute("sylva:irradiance");
  ASSERT_EQ(e, l.attribute("sylva:irradiance"));
  // "R=…,G=…,B=…,S2A_B8.Y=…": the same samples, scaled by π / E_c per channel.
  const size_t at = e.find("S2A_B8.Y=");
  ASSERT_NE(at, std::string::npos) << e;
  const double e_b8 = std::stod(e.substr(at + 9));
  EXPECT_GT(e_b8, 0.0);
  const int c = l.find_channel("S2A_B8.Y");
  for (int i = 0; i < 16 * 9; i += 7) {
    const float lv = l.pixels[size_t(i) * l.channels.size() + size_t(c)];
    const float fv = f.pixels[size_t(i) * f.channels.size() + size_t(c)];
    EXPECT_NEAR(fv, lv * std::numbers::pi / e_b8, 1e-5 * std::abs(fv) + 1e-9);
  }
  const auto bad = run_sylva("render '" SYLVA_SOURCE_DIR "/data/examples/objects.toml' -o '" +
                                 (dir / "x.exr").string() + "' --quantity brf" + common,
                             dir);
  EXPECT_EQ(bad.exit_code, 2);
}

}  // namespace
}  // namespace sylva

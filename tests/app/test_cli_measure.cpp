// `sylva measure`: the plot sensor's CSV outputs, their checks before any work, and bad requests.

#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::q;
using test::read_text;
using test::run_sylva;

const char* const kScene = R"([render]
bands = ["S2A_B4", "S2A_B8"]
[sun]
elevation = 60
[sky]
model = "none"
[materials.leaf]
type = "leaf"
reflectance = 0.45
transmittance = 0.45
[materials.soil]
reflectance = 0.2
[plot]
size = [4, 4]
cyclic = true
principal_plane = [-40, 40, 20]
samples = 500
flux_samples = 2000
ground = ["soil"]
[[meshes]]
shape = "plane"
size = [4, 4]
material = "soil"
[[canopies]]
type = "homogeneous"
lai = 1
height = 1
material = "leaf"
)";

// A shell-quoted path.

std::vector<std::string> data_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') out.push_back(line);
  return out;
}

TEST(CliMeasure, WritesBrfAndFluxTables) {
  const fs::path dir = fresh_dir("cli_measure");
  std::ofstream(dir / "plot.toml") << kScene;
  std::ostringstream args;
  args << "measure " << q(dir / "plot.toml") << " --brf " << q(dir / "brf.csv") << " --flux " << q(dir / "flux.csv")
       << " --threads 2";
  const auto r = run_sylva(args.str(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> brf = data_lines(read_text(dir / "brf.csv"));
  ASSERT_EQ(brf.size(), 6u);
  EXPECT_EQ(brf[0], "view_zenith_deg,view_azimuth_deg,signed_zenith_deg,S2A_B4.Y,S2A_B4.Y_se,S2A_B8.Y,S2A_B8.Y_se");
  EXPECT_EQ(brf[1].rfind("40,135,-40,", 0), 0u) << brf[1];  // the default sun azimuth is 135°
  const std::vector<std::string> flux = data_lines(read_text(dir / "flux.csv"));
  ASSERT_EQ(flux.size(), 3u);
  EXPECT_EQ(flux[0].rfind("channel,absorbed_leaves,absorbed_leaves_se,", 0), 0u);
  EXPECT_EQ(flux[2].rfind("S2A_B8.Y,", 0), 0u);
  // The same request again gives the same bytes (seeded, thread-count independent).
  const std::string first = read_text(dir / "brf.csv");
  std::ostringstream args1;
  args1 << "measure " << q(dir / "plot.toml") << " --brf " << q(dir / "brf.csv") << " --threads 1";
  const auto again = run_sylva(args1.str(), dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(read_text(dir / "brf.csv"), first);
}

TEST(CliMeasure, RefusesBadRequestsBeforeAnyWork) {
  const fs::path dir = fresh_dir("cli_measure_bad");
  std::ofstream(dir / "plot.toml") << kScene;
  std::ofstream(dir / "noplot.toml") << "[sky]\nmodel = \"none\"\n";
  const std::string scene = q(dir / "plot.toml");
  auto r = run_sylva("measure " + scene, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("give --brf FILE, --flux FILE or both"), std::string::npos) << r.err;
  r = run_sylva("measure " + scene + " --brf " + scene, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--brf"), std::string::npos) << r.err;
  std::ostringstream noplot;
  noplot << "measure " << q(dir / "noplot.toml") << " --flux " << q(dir / "f.csv");
  r = run_sylva(noplot.str(), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("has no [plot]"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "f.csv"));
  r = run_sylva("measure " + scene + " --brf " + q(dir / "no_such_dir" / "b.csv"), dir);
  EXPECT_EQ(r.exit_code, 2);
}

// `sylva export` keeps the discs: each a 12-sided polygon (a fan of 12 triangles) in the OBJ.
TEST(CliMeasure, ExportPolygonisesLeafDiscs) {
  const fs::path dir = fresh_dir("cli_export_discs");
  std::ofstream(dir / "plot.toml") << kScene << "[camera]\nposition = [0, -6, 3]\ntarget = [0, 0, 0.5]\n";
  const auto r = run_sylva("export " + q(dir / "plot.toml") + " --obj " + q(dir / "plot.obj"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int faces = 0;
  std::istringstream in(read_text(dir / "plot.obj"));
  std::string line;
  while (std::getline(in, line)) faces += line.rfind("f ", 0) == 0;
  const int discs = static_cast<int>(std::round(1.0 * 16.0 / (3.14159265358979 * 0.01)));  // LAI 1 on 4 × 4 m
  EXPECT_EQ(faces, 2 + 12 * discs);
}

}  // namespace
}  // namespace sylva

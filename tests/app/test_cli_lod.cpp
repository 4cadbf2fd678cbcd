// Level of detail (docs/lod.md) end to end: a stand of aspens seen obliquely from 25 m up, most of
// them far enough for the reduced levels, rendered with and without [lod]; the two images must be
// statistically indistinguishable (`sylva compare`'s engine, RGB) over the rows where the trees
// are distant, while the LOD render really draws other geometry (round-curve stems).

#include "compare/image_compare.h"
#include "core/image.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::run_sylva;

std::string stand_scene(bool lod) {
  std::string text = R"([render]
width = 96
height = 64
spp = 32
seed = 1
bands = ["rgb"]
[camera]
position = [0, -10, 25]
target = [0, 150, 0]
vfov = 30
[sun]
azimuth = 150
elevation = 40
[sky]
model = "cie"
[materials.soil]
reflectance = 0.15
[materials.bark]
reflectance = 0.3
[materials.leaf]
type = "leaf"
prospect = { N = 1.5, Cab = 40, Car = 8, Cw = 0.01, Cm = 0.009 }
[[meshes]]
shape = "plane"
size = [2000, 2000]
material = "soil"
[[placements]]
species.aspen = { species = "species/quaking_aspen.toml", bark = "bark", leaf = "leaf" }
rows = [
)";
  int k = 0;
  for (int y = 20; y < 320; y += 20)
    for (int x = -40; x < 50; x += 10) {
      ++k;
      text += "  { x = " + std::to_string(x + (k * 7) % 5 - 2) + ", y = " + std::to_string(y + (k * 3) % 7 - 3) +
              ", species = \"aspen\", seed = " + std::to_string(1 + k % 3) +
              ", heading = " + std::to_string((k * 47) % 360) + " },\n";
    }
  text += "]\n";
  text += lod ? "[lod]\nenabled = true\n" : "[lod]\nenabled = false\n";
  return text;
}

// Rows [y0, y1) of the R, G, B and var.* channels.
Image rows(const Image& img, int y0, int y1) {
  Image out;
  out.width = img.width;
  out.height = y1 - y0;
  const size_t n = img.channels.size();
  for (size_t c = 0; c < n; ++c) {
    const std::string& name = img.channels[c];
    if (name != "R" && name != "G" && name != "B" && name != "var.R" && name != "var.G" && name != "var.B") continue;
    out.channels.push_back(name);
    out.types.push_back(img.types[c]);
  }
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < img.width; ++x)
      for (const std::string& name : out.channels)
        out.pixels.push_back(img.pixels[(static_cast<size_t>(y) * img.width + x) * n + img.find_channel(name)]);
  out.attributes = img.attributes;
  return out;
}

TEST(CliLod, DistantRowsMatchTheFullForest) {
  const fs::path dir = fresh_dir("cli_lod");
  std::ofstream(dir / "lod.toml") << stand_scene(true);
  std::ofstream(dir / "full.toml") << stand_scene(false);
  const auto lod = run_sylva(
      "render '" + (dir / "lod.toml").string() + "' -o '" + (dir / "lod.exr").string() + "' --seed 7 --threads 2", dir);
  ASSERT_EQ(lod.exit_code, 0) << lod.err;
  const auto full = run_sylva(
      "render '" + (dir / "full.toml").string() + "' -o '" + (dir / "full.exr").string() + "' --threads 2", dir);
  ASSERT_EQ(full.exit_code, 0) << full.err;
  // The LOD render draws stems as curves; the full one has none.
  EXPECT_NE(full.err.find(" + 0 curves"), std::string::npos) << full.err;
  EXPECT_EQ(lod.err.find(" + 0 curves"), std::string::npos) << lod.err;

  // The top 48 rows: trees beyond ~35 m, r2 ≥ 240 (levels 1–3).
  const Image a = rows(read_exr(dir / "lod.exr"), 0, 48), b = rows(read_exr(dir / "full.exr"), 0, 48);
  // Per pixel the two are indistinguishable; the means differ by the levels' residual bias, which
  // the Sobol' sampler resolves: green +0.5 to +0.9 % (mean-bias z 2 to 4 at 32 spp; docs/lod.md),
  // bounded here at 1.2 % (the first-masses rule gave +5 to +7 %, one leaf in eight +1.4 %).
  CompareOptions options;
  options.channels = {"R", "G", "B"};
  options.bias_alpha = 0;
  const CompareResult result = compare_images(a, b, options);
  EXPECT_TRUE(result.passed) << format_compare_summary(result);
  for (const ChannelReport& c : result.channels)
    EXPECT_LT(std::abs(c.mean_rel_diff), 0.012) << c.name << "\n" << format_compare_summary(result);
}

// `sylva tree --lod`: one row per level, each cheaper in BVH memory than the one before, the leaf
// area the same in every row.
TEST(CliLod, TreeReportsEveryLevel) {
  const fs::path dir = fresh_dir("cli_lod_tree");
  const auto r = run_sylva("tree '" SYLVA_SOURCE_DIR "/data/species/quaking_aspen.toml' --quality 0.3 --lod", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::vector<double> bvh, area;
  while (std::getline(lines, line)) {
    if (line.rfind("| ", 0) != 0 || line.find("| level") == 0) continue;
    std::vector<std::string> cells;
    std::istringstream row(line);
    std::string cell;
    while (std::getline(row, cell, '|')) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 13u) << line;  // leading empty cell + 12 columns
    area.push_back(std::stod(cells[9]));
    bvh.push_back(std::stod(cells[11]));
  }
  ASSERT_EQ(bvh.size(), 4u) << r.out;
  for (size_t k = 1; k < bvh.size(); ++k) {
    EXPECT_LT(bvh[k], bvh[k - 1]) << r.out;
    EXPECT_NEAR(area[k], area[0], 0.01 * area[0]) << r.out;
  }
}

}  // namespace
}  // namespace sylva

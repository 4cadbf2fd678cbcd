// bench/replica_error.cpp (sylva_replica_error, bench/adaptive.sh's error measure): the median
// relative error over a class mask, from three replicas of a tiny synthetic render with known
// values, its var.<c> variant, the spp figures and the spp map; when the benchmarks are built.

#include "core/image.h"
#include "tests/support/temp_dir.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>

namespace sylva {
namespace {

#ifdef SYLVA_REPLICA_ERROR_TOOL
constexpr const char* kTool = SYLVA_REPLICA_ERROR_TOOL;
#else
constexpr const char* kTool = nullptr;  // the benchmarks are not built (SYLVA_BUILD_BENCH=OFF)
#endif

class ReplicaError : public test::TempDirTest {
 protected:
  // Three 2×1 replicas. Pixel 0 is class 20 (a "tree"), pixel 1 class 1 (terrain).
  // Pixel 0: R = 1, 2, 3 (mean 2, s² = 1), G = 2 always, B = 4 always; spp 16, 64, 64.
  // Pixel 1: R = 10, 10, 13 (mean 11, s² = 3), G = B = 1 always; spp 64.
  // var.<c> = 0.01 everywhere.
  void SetUp() override {
    TempDirTest::SetUp();
    const float r0[3] = {1, 2, 3}, r1[3] = {10, 10, 13}, spp0[3] = {16, 64, 64};
    for (int k = 0; k < 3; ++k) {
      Image image = make_image(2, 1, {"R", "G", "B", "var.R", "var.G", "var.B", "id.class", "spp"});
      const float pixel[2][8] = {{r0[k], 2, 4, 0.01f, 0.01f, 0.01f, 20, spp0[k]},
                                 {r1[k], 1, 1, 0.01f, 0.01f, 0.01f, 1, 64}};
      for (int x = 0; x < 2; ++x)
        for (int c = 0; c < 8; ++c) image.at(x, 0, c) = pixel[x][c];
      write_exr(replica(k), image);
    }
  }

  std::filesystem::path replica(int k) const { return dir_ / fmt::format("r{}.exr", k); }

  // Runs the tool with ARGS before the three replicas; its "key value" lines (empty on failure).
  std::map<std::string, double> run(const std::string& args) const {
    const std::string out = (dir_ / "out.txt").string();
    std::string cmd = fmt::format("{} {}", kTool, args);
    for (int k = 0; k < 3; ++k) cmd += fmt::format(" '{}'", replica(k).string());
    std::map<std::string, double> values;
    if (std::system(fmt::format("{} > '{}'", cmd, out).c_str()) != 0) return values;
    std::ifstream in(out);
    std::string key;
    for (double v = 0; in >> key >> v;) values[key] = v;
    return values;
  }
};

const double kPixel0 = std::sqrt((0.25 + 0 + 0) / 3);         // R: √1 / 2; G, B: no spread
const double kPixel1 = std::sqrt((3.0 / 121.0 + 0 + 0) / 3);  // R: √3 / 11
const double kPixel0Var = std::sqrt((0.01 / 4 + 0.01 / 4 + 0.01 / 16) / 3);

TEST_F(ReplicaError, MedianOverTheClassMask) {
  if (kTool == nullptr) GTEST_SKIP() << "the benchmarks are not built (SYLVA_BUILD_BENCH=OFF)";
  std::map<std::string, double> v = run("--classes 20,99");
  ASSERT_FALSE(v.empty());
  EXPECT_EQ(v["pixels"], 1);
  EXPECT_NEAR(v["median"], kPixel0, 1e-5 * kPixel0);
  EXPECT_NEAR(v["median.R"], 0.5, 1e-5);
  EXPECT_EQ(v["median.G"], 0);
  EXPECT_NEAR(v["median_var"], kPixel0Var, 1e-5 * kPixel0Var);
  EXPECT_NEAR(v["mean_spp"], 48, 1e-9);
  EXPECT_EQ(v["median_spp"], 64);
  EXPECT_EQ(v["max_spp"], 64);
  EXPECT_NEAR(v["at_max_spp"], 2.0 / 3.0, 1e-5);

  v = run("");  // every pixel: the median of two is their mean
  EXPECT_EQ(v["pixels"], 2);
  EXPECT_NEAR(v["median"], (kPixel0 + kPixel1) / 2, 1e-5);
  EXPECT_NEAR(v["p25"], kPixel1 + 0.25 * (kPixel0 - kPixel1), 1e-5);
  EXPECT_NEAR(v["mean_spp"], (48 + 64) / 2.0, 1e-9);

  v = run("--channels R --classes 1");
  EXPECT_NEAR(v["median"], std::sqrt(3.0) / 11, 1e-5);
}

TEST_F(ReplicaError, SppMapAndErrors) {
  if (kTool == nullptr) GTEST_SKIP() << "the benchmarks are not built (SYLVA_BUILD_BENCH=OFF)";
  const std::filesystem::path png = dir_ / "spp.png";
  ASSERT_FALSE(run("--spp-png '" + png.string() + "'").empty());
  const Image map = read_exr(png);  // any format OpenImageIO or libpng reads
  EXPECT_EQ(map.width, 4);          // the image, then its spp map
  EXPECT_EQ(map.height, 1);
  EXPECT_NEAR(map.at(2, 0, 0), 4.0 / 6.0, 1.0 / 255);  // log2 16 / log2 64 of the first replica
  EXPECT_NEAR(map.at(3, 0, 0), 1.0, 1.0 / 255);
  const std::filesystem::path big = dir_ / "spp3.png";
  ASSERT_FALSE(run("--spp-png '" + big.string() + "' --scale 3").empty());
  const Image scaled = read_exr(big);
  EXPECT_EQ(scaled.width, 12);
  EXPECT_EQ(scaled.height, 3);
  EXPECT_EQ(scaled.at(8, 2, 0), map.at(2, 0, 0));
  EXPECT_TRUE(run("--channels nir.Y").empty());  // no such channel: exit 2
  const std::string one = fmt::format("{} '{}' 2>/dev/null", kTool, replica(0).string());
  EXPECT_NE(std::system(one.c_str()), 0);  // a single replica has no spread
}

}  // namespace
}  // namespace sylva

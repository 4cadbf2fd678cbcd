// Leaf discs: the RAMI leaf-file reader (file:line errors) and the canopy generators (counts, extents,
// leaf-angle distributions, determinism).

#include "core/error.h"
#include "geometry/leaf_discs.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace sylva {
namespace {

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / ("sylva_discs_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(LeafDiscs, ReadsRamiRowsAndNormalisesNormals) {
  const auto p = write_temp("ok.txt", "# radius cx cy cz nx ny nz\n\n0.1 1 2 3 0 0 2\n  0.05\t-1 0 0.5  3 0 4\n");
  const LeafDiscs d = read_leaf_discs(p);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_FLOAT_EQ(d.radius[0], 0.1f);
  EXPECT_EQ(d.centre[0], Vec3(1, 2, 3));
  EXPECT_EQ(d.normal[0], Vec3(0, 0, 1));
  EXPECT_NEAR(d.normal[1].x, 0.6f, 1e-6f);
  EXPECT_NEAR(d.normal[1].z, 0.8f, 1e-6f);
  EXPECT_NEAR(d.area(), kPi * (0.01 + 0.0025), 1e-6);
  std::filesystem::remove(p);
}

TEST(LeafDiscs, EveryMistakeNamesFileAndLine) {
  const std::pair<std::string, std::string> cases[] = {
      {"0.1 0 0 0 0 0 1\n0.1 0 0 0 0 1\n", ":2: expected 7 numbers (radius cx cy cz nx ny nz), found 6"},
      {"# c\n0.1 0 0 0 0 0 1 5\n", ":2: expected 7 numbers (radius cx cy cz nx ny nz), found more"},
      {"0.1 0 0 x 0 0 1\n", ":1: expected a number in column 4"},
      {"0.1 0 0 1e99 0 0 1\n", ":1: expected a number in column 4"},
      {"0 0 0 0 0 0 1\n", ":1: the disc radius must be positive"},
      {"\n\n0.1 0 0 0 0 0 0\n", ":3: the disc normal must not be zero"},
      {"# only a comment\n", ":1: the leaf file holds no leaves"},
  };
  for (const auto& [text, expected] : cases) {
    const auto p = write_temp("bad.txt", text);
    try {
      read_leaf_discs(p);
      ADD_FAILURE() << "no error for:\n" << text;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.file(), p);
      EXPECT_NE(std::string(e.what()).find(p.string() + expected), std::string::npos) << e.what();
    }
    std::filesystem::remove(p);
  }
  EXPECT_THROW(read_leaf_discs("/nonexistent/leaves.txt"), Error);
}

TEST(LeafDiscs, PointFilesRead) {
  const auto p = write_temp("points.txt", "# centres\n1 2 3\n-4 5.5 6\n");
  const std::vector<Vec3> pts = read_points(p);
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(pts[1], Vec3(-4, 5.5f, 6));
  std::filesystem::remove(p);
  const auto bad = write_temp("badpoints.txt", "1 2 3\n1 2\n");
  EXPECT_THROW(read_points(bad), ParseError);
  std::filesystem::remove(bad);
}

// Mean cos θ_L of each de Wit distribution: spherical 1/2, planophile 8/(3π), erectophile 4/(3π).
TEST(LeafDiscs, LeafAngleDistributionsHaveTheirMeanInclination) {
  const std::pair<LeafAngles, double> cases[] = {{LeafAngles::spherical, 0.5},
                                                 {LeafAngles::planophile, 8.0 / (3.0 * kPi)},
                                                 {LeafAngles::erectophile, 4.0 / (3.0 * kPi)}};
  for (const auto& [angles, expected] : cases) {
    const LeafDiscs d = make_homogeneous_layer(Vec2(-5), Vec2(5), 2.0f, 2.0f, 0.1f, angles, 7);
    double sum = 0, sum2 = 0;
    for (const Vec3& n : d.normal) {
      EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
      sum += n.z;
      sum2 += n.z * n.z;
    }
    const double count = static_cast<double>(d.size());
    const double mean = sum / count, se = std::sqrt((sum2 / count - mean * mean) / count);
    EXPECT_LT(std::abs(mean - expected), 4 * se) << static_cast<int>(angles) << ": " << mean << " vs " << expected;
  }
  EXPECT_EQ(parse_leaf_angles("uniform"), LeafAngles::spherical);
  EXPECT_THROW(parse_leaf_angles("plagiophile"), Error);
}

TEST(LeafDiscs, HomogeneousLayerHoldsItsLeafAreaInsideTheLayer) {
  const LeafDiscs d = make_homogeneous_layer(Vec2(-2, 1), Vec2(4, 5), 2.0f, 3.0f, 0.1f, LeafAngles::erectophile, 3);
  EXPECT_EQ(d.size(), static_cast<size_t>(std::round(3.0 * 24.0 / (kPi * 0.01))));
  EXPECT_NEAR(d.area() / 24.0, 3.0, 1e-3);
  for (size_t i = 0; i < d.size(); ++i) {
    EXPECT_TRUE(d.centre[i].x >= -2 && d.centre[i].x <= 4 && d.centre[i].y >= 1 && d.centre[i].y <= 5);
    EXPECT_TRUE(d.centre[i].z >= 0.1f && d.centre[i].z <= 1.9f);
  }
  const LeafDiscs again = make_homogeneous_layer(Vec2(-2, 1), Vec2(4, 5), 2.0f, 3.0f, 0.1f, LeafAngles::erectophile, 3);
  EXPECT_EQ(again.centre, d.centre);
  EXPECT_EQ(again.normal, d.normal);
  EXPECT_NE(make_homogeneous_layer(Vec2(-2, 1), Vec2(4, 5), 2.0f, 3.0f, 0.1f, LeafAngles::erectophile, 4).centre,
            d.centre);
  EXPECT_THROW(make_homogeneous_layer(Vec2(0), Vec2(1), 0.1f, 3.0f, 0.1f, LeafAngles::spherical, 1), Error);
}

// RAMI-3 HET01: a sphere of radius 10 m with LAI 5 of discs of radius 0.1 m holds 50,000 of them
// (RAMI's file has 49,999), centres uniform in the sphere (mean (|c|/R)³ = 1/2, as in RAMI's file).
TEST(LeafDiscs, SphereOfDiscsMatchesHet01) {
  const LeafDiscs d = make_leaf_sphere(10.0f, 5.0f, 0.1f, LeafAngles::spherical, 1);
  EXPECT_EQ(d.size(), 50000u);
  double sum = 0, sum2 = 0;
  for (const Vec3& c : d.centre) {
    const double r3 = std::pow(glm::length(c) / 10.0, 3.0);
    EXPECT_LE(r3, 1.0 + 1e-5);
    sum += r3;
    sum2 += r3 * r3;
  }
  const double n = static_cast<double>(d.size()), mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_LT(std::abs(mean - 0.5), 4 * se);
}

}  // namespace
}  // namespace sylva

// The benchmarks' relMSE (compare/rel_mse.h): known values on tiny images written to EXR and read
// back, issue 41's definition and the denoiser's variant, and the sylva_rel_mse tool on the same
// files (when the benchmarks are built).

#include "compare/rel_mse.h"
#include "core/error.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace sylva {
namespace {

class RelMse : public test::TempDirTest {
 protected:
  // 2×1 images: ref R = (1, 3), G = (2, 2), B = (0.5, 0.5); test R = (2, 3), G = (2, 1), B = ref's.
  void SetUp() override {
    TempDirTest::SetUp();
    Image ref = make_image(2, 1, {"R", "G", "B", "var.R", "var.G", "var.B"});
    Image test = make_image(2, 1, {"R", "G", "B"});
    const float r[2][3] = {{1, 2, 0.5f}, {3, 2, 0.5f}}, t[2][3] = {{2, 2, 0.5f}, {3, 1, 0.5f}};
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 3; ++c) {
        ref.at(x, 0, c) = r[x][c];
        ref.at(x, 0, 3 + c) = 0.25f;
        test.at(x, 0, c) = t[x][c];
      }
    write_exr(dir_ / "ref.exr", ref);
    write_exr(dir_ / "test.exr", test);
  }
  Image ref() const { return read_exr(dir_ / "ref.exr"); }
  Image test() const { return read_exr(dir_ / "test.exr"); }
};

// ε_R = 10⁻⁴ · (1 + 9) / 2, ε_G = 10⁻⁴ · 4: R's error 1 at the first pixel, G's 1 at the second.
const double kIssue41 = (1.0 / (1.0 + 5e-4) + 1.0 / (4.0 + 4e-4)) / 6.0;

TEST_F(RelMse, Issue41DefinitionOnTinyExrs) {
  EXPECT_NEAR(relative_mse(test(), ref()), kIssue41, 1e-12);
  const std::vector<double> per_pixel = relative_squared_errors(test(), ref(), issue41_rel_mse());
  ASSERT_EQ(per_pixel.size(), 2u);
  EXPECT_NEAR(per_pixel[0], 1.0 / (1.0 + 5e-4) / 3.0, 1e-12);
  EXPECT_NEAR(per_pixel[1], 1.0 / (4.0 + 4e-4) / 3.0, 1e-12);
  EXPECT_EQ(relative_mse(ref(), ref()), 0.0);
}

TEST_F(RelMse, TheDenoiserVariantSubtractsTheReferenceVariance) {
  RelMseOptions o;
  o.channels = beauty_channels(ref());
  EXPECT_EQ(o.channels, (std::vector<std::string>{"R", "G", "B"}));
  o.epsilon_scale = 1e-2;
  o.epsilon = RelMseEpsilon::square_mean;
  o.subtract_reference_variance = true;
  // ε_R = 10⁻² · 2², ε_G = 10⁻² · 2², ε_B = 10⁻² · 0.5²; every pixel-channel loses Var = 0.25.
  const double expected = ((1 - 0.25) / (1 + 0.04) + (-0.25) / (9 + 0.04) + (-0.25) / (4 + 0.04) +
                           (1 - 0.25) / (4 + 0.04) + 2 * (-0.25) / (0.25 + 0.0025)) /
                          6.0;
  EXPECT_NEAR(relative_mse(test(), ref(), o), expected, 1e-12);
}

TEST_F(RelMse, RowsChannelsAndSizesAreChecked) {
  RelMseOptions o;
  o.channels = {"R"};
  o.row_begin = 1;
  EXPECT_THROW(relative_mse(test(), ref(), o), Error);  // one row: row 1 is outside
  o.row_begin = 0;
  EXPECT_NEAR(relative_mse(test(), ref(), o), 1.0 / (1.0 + 5e-4) / 2.0, 1e-12);
  o.channels = {"nir.Y"};
  EXPECT_THROW(relative_mse(test(), ref(), o), Error);
  o.channels = {"R"};
  o.subtract_reference_variance = true;
  EXPECT_THROW(relative_mse(ref(), test(), o), Error);  // the test image has no var.R
  EXPECT_THROW(relative_mse(make_image(1, 1, {"R", "G", "B"}), ref()), Error);
}

TEST_F(RelMse, TheToolPrintsTheIssue41Value) {
#ifdef SYLVA_REL_MSE_TOOL
  const std::string out = (dir_ / "out.txt").string();
  const std::string cmd = std::string(SYLVA_REL_MSE_TOOL) + " '" + (dir_ / "test.exr").string() + "' '" +
                          (dir_ / "ref.exr").string() + "' > '" + out + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  FILE* f = std::fopen(out.c_str(), "r");
  ASSERT_NE(f, nullptr);
  double value = -1;
  EXPECT_EQ(std::fscanf(f, "%lf", &value), 1);
  std::fclose(f);
  EXPECT_NEAR(value, kIssue41, 1e-6 * kIssue41);  // printed with 6 significant digits
  const std::string missing = std::string(SYLVA_REL_MSE_TOOL) + " '" + (dir_ / "test.exr").string() + "' '" +
                              (dir_ / "none.exr").string() + "' 2>/dev/null";
  EXPECT_NE(std::system(missing.c_str()), 0);
#else
  GTEST_SKIP() << "the benchmarks are not built (SYLVA_BUILD_BENCH=OFF)";
#endif
}

}  // namespace
}  // namespace sylva

// `sylva compare` end to end: exit codes 0/1/2, summary, companion variance files, threshold
// fallback, report directory. Runs the built binary (SYLVA_BINARY) on synthetic EXRs.

#include "core/image.h"
#include "tests/support/run_command.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;

using test::CommandResult;
using test::read_text;

class CompareCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        test::fresh_dir(std::string("cmd_compare_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { fs::remove_all(dir_); }

  CommandResult run(const std::string& args) const { return test::run_sylva("compare " + args, dir_); }
  std::string path(const std::string& name) const {
    std::string quoted = "'";
    quoted += (dir_ / name).string();
    quoted += '\'';
    return quoted;
  }

  // R,G,B (+ var.*) drawn like a Monte Carlo estimate with `spp` samples of relative σ 0.5.
  void write(const std::string& name, int spp, float scale, uint64_t seed, bool variance = true, int size = 32) const {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    std::gamma_distribution<double> chi2_half((spp - 1) / 2.0, 2.0);
    Image image = make_image(size, size, {"R", "G", "B"});
    if (variance)
      for (const char* v : {"var.R", "var.G", "var.B"}) image.add_channel(v, PixelType::Float);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        for (int c = 0; c < 3; ++c) {
          const double mu = scale * ((((x / 4) + (y / 4) + c) % 2 == 0) ? 0.8 : 0.2);
          const double var = std::pow(0.5 * mu, 2) / spp;
          image.at(x, y, c) = static_cast<float>(mu + normal(rng) * std::sqrt(var));
          const double estimate = var * chi2_half(rng) / (spp - 1);
          if (variance) image.at(x, y, 3 + c) = static_cast<float>(estimate);
        }
    image.attributes = {{"sylva:spp", std::to_string(spp)}};
    write_exr(dir_ / name, image);
  }

  fs::path dir_;
};

TEST_F(CompareCommand, SameDistributionPassesAndBiasFails) {
  write("ref.exr", 4096, 1.0f, 1);
  write("test.exr", 64, 1.0f, 2);
  write("bright.exr", 64, 1.03f, 3);
  const CommandResult pass = run(path("test.exr") + " " + path("ref.exr"));
  EXPECT_EQ(pass.exit_code, 0) << pass.out << pass.err;
  EXPECT_NE(pass.out.find("PASS"), std::string::npos) << pass.out;
  EXPECT_NE(pass.out.find("rejecting pixel-channels"), std::string::npos) << pass.out;
  EXPECT_NE(pass.out.find("worst: pixel ("), std::string::npos) << pass.out;

  const CommandResult fail = run(path("bright.exr") + " " + path("ref.exr"));
  EXPECT_EQ(fail.exit_code, 1) << fail.out << fail.err;
  EXPECT_NE(fail.out.find("FAIL"), std::string::npos) << fail.out;
  EXPECT_NE(fail.out.find("mean-bias test FAILED"), std::string::npos) << fail.out;
}

TEST_F(CompareCommand, UnusableInputExitsTwoWithAClearMessage) {
  write("ref.exr", 4096, 1.0f, 1);
  write("small.exr", 64, 1.0f, 2, true, 16);
  const CommandResult missing = run(path("nope.exr") + " " + path("ref.exr"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("sylva: " + (dir_ / "nope.exr").string() + ": no such file"), std::string::npos)
      << missing.err;
  const CommandResult size = run(path("small.exr") + " " + path("ref.exr"));
  EXPECT_EQ(size.exit_code, 2);
  EXPECT_NE(size.err.find("size mismatch: test is 16x16, reference is 32x32"), std::string::npos) << size.err;
  const CommandResult channel = run(path("ref.exr") + " " + path("ref.exr") + " --channels R,nir.Y");
  EXPECT_EQ(channel.exit_code, 2);
  EXPECT_NE(channel.err.find("nir.Y"), std::string::npos) << channel.err;
  const CommandResult limit = run(path("ref.exr") + " " + path("ref.exr") + " --max-reject lots");
  EXPECT_EQ(limit.exit_code, 2);
  EXPECT_NE(limit.err.find("--max-reject"), std::string::npos) << limit.err;
  const CommandResult no_args = run("");
  EXPECT_EQ(no_args.exit_code, 2);
}

TEST_F(CompareCommand, SameSeedAndOtherSettingsAreRefusedUnlessIntended) {
  write("ref.exr", 4096, 1.0f, 1);
  write("test.exr", 64, 1.0f, 2);
  const auto stamp = [&](const std::string& name, const std::string& seed, const std::string& bands) {
    Image image = read_exr(dir_ / name);
    image.set_attribute("sylva:seed", seed);
    image.set_attribute("sylva:bands", bands);
    write_exr(dir_ / name, image);
  };
  stamp("ref.exr", "1", "rgb");
  stamp("test.exr", "1", "rgb");
  const std::string both = path("test.exr") + " " + path("ref.exr");
  const CommandResult same = run(both);
  EXPECT_EQ(same.exit_code, 2) << same.out << same.err;
  EXPECT_NE(same.err.find("sylva: refused: the test and reference have the same seed (1)"), std::string::npos)
      << same.err;
  const CommandResult allowed = run(both + " --allow-same-seed");
  EXPECT_EQ(allowed.exit_code, 0) << allowed.out << allowed.err;
  EXPECT_NE(allowed.out.find("note: the test and reference have the same seed"), std::string::npos) << allowed.out;
  stamp("test.exr", "2", "rgb,nir");
  const CommandResult bands = run(both);
  EXPECT_EQ(bands.exit_code, 2) << bands.out << bands.err;
  EXPECT_NE(bands.err.find("sylva:bands differs: test rgb,nir, reference rgb (pass --allow-difference bands"),
            std::string::npos)
      << bands.err;
  EXPECT_EQ(run(both + " --allow-difference bands").exit_code, 0);
  EXPECT_EQ(run(both + " --allow-difference colour").exit_code, 2);
}

TEST_F(CompareCommand, CompanionVarianceFile) {
  write("ref_full.exr", 4096, 1.0f, 1);
  write("test.exr", 64, 1.0f, 2, false);
  write("bright.exr", 64, 1.1f, 3, false);
  // Split the reference into a mean file and a companion variance file with plain channel names.
  const Image full = read_exr(dir_ / "ref_full.exr");
  Image mean = make_image(full.width, full.height, {"R", "G", "B"});
  Image var = make_image(full.width, full.height, {"R", "G", "B"});
  for (int y = 0; y < full.height; ++y)
    for (int x = 0; x < full.width; ++x)
      for (const char* c : {"R", "G", "B"}) {
        mean.at(x, y, mean.find_channel(c)) = full.at(x, y, full.find_channel(c));
        var.at(x, y, var.find_channel(c)) = full.at(x, y, full.find_channel(std::string("var.") + c));
      }
  mean.attributes = full.attributes;
  write_exr(dir_ / "ref.exr", mean);
  write_exr(dir_ / "ref_var.exr", var);
  const CommandResult no_var = run(path("test.exr") + " " + path("ref.exr"));
  EXPECT_EQ(no_var.exit_code, 2) << no_var.out;
  EXPECT_NE(no_var.err.find("--ref-var"), std::string::npos) << no_var.err;
  const CommandResult pass = run(path("test.exr") + " " + path("ref.exr") + " --ref-var " + path("ref_var.exr"));
  EXPECT_EQ(pass.exit_code, 0) << pass.out << pass.err;
  const CommandResult fail = run(path("bright.exr") + " " + path("ref.exr") + " --ref-var " + path("ref_var.exr"));
  EXPECT_EQ(fail.exit_code, 1) << fail.out << fail.err;
}

TEST_F(CompareCommand, ThresholdFallbackAndTolerances) {
  Image ref = make_image(10, 10, {"R", "G", "B", "Z"});
  ref.add_channel("id.object", PixelType::UInt);
  Image test = ref;
  test.at(1, 1, 0) = 0.02f;
  test.at(2, 2, 1) = 0.02f;
  test.at(5, 5, 3) = 0.0005f;
  write_exr(dir_ / "ref.exr", ref);
  write_exr(dir_ / "test.exr", test);
  const std::string both = path("test.exr") + " " + path("ref.exr");
  EXPECT_EQ(run(both + " --channels R,G,B --fail 0.016 --fail-percent 1").exit_code,
            1);  // 2% of pixels fail
  EXPECT_EQ(run(both + " --channels R,G,B --fail 0.016 --fail-percent 2").exit_code, 0);
  EXPECT_EQ(run(both + " --channels R,G,B --fail 0.05").exit_code, 0);
  EXPECT_EQ(run(both + " --channels Z --abs-tol-channel Z=0.001 --max-reject 0").exit_code, 0);
  EXPECT_EQ(run(both + " --channels Z --abs-tol-channel Z=0.0001 --max-reject 0").exit_code, 1);
  EXPECT_EQ(run(both + " --channels id.object --max-reject 0").exit_code, 0);
  EXPECT_EQ(run(both + " --channels Z --abs-tol-channel Z").exit_code, 2);
  EXPECT_EQ(run(both + " --fail-percent 1").exit_code, 2);  // needs --fail
}

TEST_F(CompareCommand, ReportDirectory) {
  write("ref.exr", 4096, 1.0f, 1);
  write("bright.exr", 64, 1.2f, 3);
  const fs::path report = dir_ / "report";
  const CommandResult fail = run(path("bright.exr") + " " + path("ref.exr") + " --report '" + report.string() + "'");
  EXPECT_EQ(fail.exit_code, 1) << fail.out << fail.err;
  for (const char* f : {"index.html", "test.exr", "ref.exr", "error.exr", "pvalue.exr", "rgb_test.png", "rgb_ref.png",
                        "rgb_diff.png", "rgb_reject.png"})
    EXPECT_TRUE(fs::exists(report / f)) << f;
  const std::string html = read_text(report / "index.html");
  EXPECT_NE(html.find("id=\"verdict\">FAIL"), std::string::npos);
  EXPECT_NE(html.find("bright.exr"), std::string::npos);

  // An unknown view is refused before anything is written.
  const fs::path nowhere = dir_ / "report2";
  const CommandResult view =
      run(path("bright.exr") + " " + path("ref.exr") + " --view Filmic --report '" + nowhere.string() + "'");
  EXPECT_EQ(view.exit_code, 2);
  EXPECT_NE(view.err.find("Standard, ACES, Raw"), std::string::npos) << view.err;
  EXPECT_FALSE(fs::exists(nowhere));
}

}  // namespace
}  // namespace sylva

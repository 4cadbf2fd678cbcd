// Finding Sylva's data and the files scene and species files name (core/data_path.h): the naming
// file's folder first, then the data directory, then its examples/ folder; $SYLVA_DATA_DIR first.

#include "core/data_path.h"

#include "core/error.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

namespace sylva {
namespace {

class DataPath : public test::TempDirTest {};

// Sets an environment variable for one scope, restoring what was there.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST_F(DataPath, TheBuildFindsTheSourceTreesData) {
  ScopedEnv none("SYLVA_DATA_DIR", "");
  ScopedEnv older("SYLVA_DATA", "");
  EXPECT_TRUE(std::filesystem::exists(data_dir() / "cie1931_2deg_cmf_1nm.csv")) << data_dir();
  EXPECT_TRUE(std::filesystem::exists(data_file("species/quaking_aspen.toml")));
}

TEST_F(DataPath, EnvironmentOverridesTheDataDirectory) {
  ScopedEnv env("SYLVA_DATA_DIR", dir_.string());
  EXPECT_EQ(data_dir(), dir_);
  EXPECT_THROW(data_file("cie1931_2deg_cmf_1nm.csv"), Error);
}

TEST_F(DataPath, NamedFilesBesideTheNamingFileThenInData) {
  ScopedEnv none("SYLVA_DATA_DIR", "");
  ScopedEnv older("SYLVA_DATA", "");
  const std::filesystem::path data = data_dir();
  // A copied example: ../species/x.toml is not beside it, but is where examples/ would find it.
  const FileLookup species = find_named_file(dir_, "../species/quaking_aspen.toml");
  EXPECT_EQ(species.found, (data / "examples/../species/quaking_aspen.toml").lexically_normal());
  ASSERT_EQ(species.tried.size(), 3u);
  EXPECT_EQ(species.tried[0], dir_ / "../species/quaking_aspen.toml");
  // A data-relative name.
  EXPECT_EQ(find_named_file(dir_, "spectra/target_paints.csv").found, data / "spectra/target_paints.csv");
  // A file beside the naming file wins over the data directory's.
  std::filesystem::create_directories(dir_ / "spectra");
  std::ofstream(dir_ / "spectra/target_paints.csv") << "lambda_nm,x\n400,0.5\n";
  EXPECT_EQ(find_named_file(dir_, "spectra/target_paints.csv").found, dir_ / "spectra/target_paints.csv");
  // Missing everywhere: nothing found, every place listed.
  const FileLookup missing = find_named_file(dir_, "nope.csv");
  EXPECT_TRUE(missing.found.empty());
  EXPECT_EQ(missing.tried.size(), 3u);
  // Absolute names are taken as they are.
  EXPECT_EQ(find_named_file(dir_, (dir_ / "spectra/target_paints.csv").string()).tried.size(), 1u);
}

}  // namespace
}  // namespace sylva

#pragma once
// A test fixture with a fresh, empty directory per test, <temp>/sylva_<suite>_<pid>_<test>, removed
// afterwards (with the owner's permissions restored first, for tests that take them away).

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

namespace sylva::test {

class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("sylva_" + std::string(info->test_suite_name()) + "_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::permissions(dir_, std::filesystem::perms::owner_all, std::filesystem::perm_options::add, ignored);
    std::filesystem::remove_all(dir_, ignored);
  }

  std::filesystem::path dir_;
};

}  // namespace sylva::test

// Untrusted input files (core/input_file.h): regular files only, read without blocking and within
// a size limit (issue 16: a FIFO or /dev/zero given as a scene or image hung forever).

#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <functional>

namespace sylva {
namespace {

namespace fs = std::filesystem;

class InputFile : public test::TempDirTest {};

std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const ParseError& e) {
    return e.what();
  }
  return "accepted";
}

TEST_F(InputFile, ReadsRegularFilesAndHashesThemLikeTheirText) {
  const std::string text = "a scene\nwith two lines\n";
  std::ofstream(dir_ / "a.toml", std::ios::binary) << text;
  EXPECT_EQ(read_input_file(dir_ / "a.toml", 1000, "scene file"), text);
  EXPECT_EQ(fnv1a64_of_file(dir_ / "a.toml", 1000, "scene file"), fnv1a64(text));
  std::ofstream(dir_ / "empty.toml");
  EXPECT_EQ(read_input_file(dir_ / "empty.toml", 1000, "scene file"), "");
}

TEST_F(InputFile, RefusesFifosDevicesDirectoriesWithoutWaiting) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  fs::create_directory(dir_ / "dir");
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NE(input_error([&] {
              read_input_file(dir_ / "fifo", 1000, "scene file");
            }).find("fifo:0: cannot read scene file: a FIFO"),
            std::string::npos);
  EXPECT_NE(input_error([&] { read_input_file("/dev/zero", 1000, "image"); }).find("cannot read image: a device"),
            std::string::npos);
  EXPECT_NE(input_error([&] { read_input_file(dir_ / "dir", 1000, "mesh"); }).find("cannot read mesh: a directory"),
            std::string::npos);
  EXPECT_NE(input_error([&] { require_regular_file(dir_ / "fifo", "image"); }).find("a FIFO"), std::string::npos);
  EXPECT_NE(input_error([&] { read_input_file(dir_ / "missing", 1000, "mesh"); }).find("cannot open mesh"),
            std::string::npos);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST_F(InputFile, RefusesFilesOverTheLimit) {
  std::ofstream(dir_ / "big.toml") << std::string(1001, 'x');
  EXPECT_NE(input_error([&] {
              read_input_file(dir_ / "big.toml", 1000, "scene file");
            }).find("scene file of 1001 bytes is larger than the limit of 1000 bytes"),
            std::string::npos);
  EXPECT_EQ(read_input_file(dir_ / "big.toml", 1001, "scene file").size(), 1001u);
}

}  // namespace
}  // namespace sylva

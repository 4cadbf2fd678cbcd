// Output checks before any work (core/output_paths.h, issue 16): an output may not be an input or
// another output (after symlinks), not an existing device, FIFO or directory, and its directory
// must exist.

#include "core/error.h"
#include "core/output_paths.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <climits>
#include <fstream>
#include <functional>

namespace sylva {
namespace {

namespace fs = std::filesystem;

class OutputPaths : public test::TempDirTest {};

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

TEST_F(OutputPaths, AnOutputMayNotBeAnInputEvenThroughASymlinkOrDotDot) {
  std::ofstream(dir_ / "s.toml") << "x";
  fs::create_directory(dir_ / "sub");
  fs::create_symlink(dir_ / "s.toml", dir_ / "link.exr");
  const std::vector<fs::path> inputs{dir_ / "s.toml"};
  for (const fs::path& out : {dir_ / "s.toml", dir_ / "link.exr", dir_ / "sub" / ".." / "s.toml"}) {
    const std::string msg = message_of([&] { check_outputs({{"-o", out}}, inputs); });
    EXPECT_NE(msg.find("is the input"), std::string::npos) << out << ": " << msg;
  }
  EXPECT_EQ(message_of([&] { check_outputs({{"-o", dir_ / "out.exr"}}, inputs); }), "accepted");
  EXPECT_EQ(message_of([&] { check_outputs({{"-o", dir_ / "out.exr"}, {"--png", {}}}, inputs); }), "accepted");
}

TEST_F(OutputPaths, TwoOutputsMayNotBeOneFile) {
  const std::string msg = message_of([&] {
    check_outputs({{"-o", dir_ / "a.exr"}, {"--png", dir_ / "." / "a.exr"}}, {});
  });
  EXPECT_NE(msg.find("--png"), std::string::npos) << msg;
  EXPECT_NE(msg.find("the same file as -o"), std::string::npos) << msg;
}

TEST_F(OutputPaths, NonRegularFilesAndMissingDirectoriesAreRefused) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  fs::create_directory(dir_ / "dir.exr");
  EXPECT_NE(message_of([&] {
              check_outputs({{"-o", dir_ / "fifo"}}, {});
            }).find("exists and is a FIFO"),
            std::string::npos);
  EXPECT_NE(message_of([&] {
              check_outputs({{"-o", "/dev/null"}}, {});
            }).find("exists and is a device"),
            std::string::npos);
  EXPECT_NE(message_of([&] {
              check_outputs({{"-o", dir_ / "dir.exr"}}, {});
            }).find("exists and is a directory"),
            std::string::npos);
  EXPECT_NE(message_of([&] {
              check_outputs({{"--obj", dir_ / "nope" / "t.obj"}}, {});
            }).find("does not exist"),
            std::string::npos);
  EXPECT_NE(message_of([&] {
              check_outputs({{"--obj", dir_ / std::string(NAME_MAX + 1, 'n')}}, {});
            }).find("longer than"),
            std::string::npos);
  // A symlink to a regular file (or to where one will be) is fine: it is written through.
  fs::create_symlink(dir_ / "target.exr", dir_ / "dangling.exr");
  EXPECT_EQ(message_of([&] { check_outputs({{"-o", dir_ / "dangling.exr"}}, {}); }), "accepted");
  EXPECT_EQ(resolved_output(dir_ / "dangling.exr"), fs::canonical(dir_) / "target.exr");
}

}  // namespace
}  // namespace sylva

// Atomic file output (core/atomic_file.h): complete files or none, the old target kept on failure,
// no temporaries left, long names, concurrent writers.

#include "core/atomic_file.h"
#include "core/error.h"
#include "tests/support/atomic_temporaries.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace sylva {
namespace {

namespace fs = std::filesystem;

class AtomicFile : public test::TempDirTest {
 protected:
  static std::string read(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static void put(const fs::path& file, const std::string& bytes) { std::ofstream(file, std::ios::binary) << bytes; }
  std::vector<std::string> temporaries() const { return test::atomic_temporaries_in(dir_); }
};

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST_F(AtomicFile, WritesAndReplaces) {
  const fs::path file = dir_ / "out.bin";
  const std::string first("binary\0bytes\n", 13);
  write_file_atomic(file, [&](std::ostream& out) { out << first; });
  EXPECT_EQ(read(file), first);
  write_file_atomic(file, [](std::ostream& out) { out << "second"; });
  EXPECT_EQ(read(file), "second");
  EXPECT_TRUE(temporaries().empty());
}

TEST_F(AtomicFile, LargeOutputIsComplete) {
  // Several times the stream's buffer, in pieces of odd sizes.
  std::string expected;
  for (int i = 0; expected.size() < 3'000'000; ++i) expected += std::string(static_cast<size_t>(i % 997), 'a' + i % 26);
  const fs::path file = dir_ / "large.bin";
  write_file_atomic(file, [&](std::ostream& out) {
    for (size_t at = 0; at < expected.size(); at += 12345) out << expected.substr(at, 12345);
  });
  EXPECT_EQ(read(file), expected);
}

TEST_F(AtomicFile, FailedWriterLeavesTargetIntactAndNoTemporary) {
  const fs::path file = dir_ / "keep.txt";
  put(file, "old contents");
  // A sylva::Error passes through unchanged.
  EXPECT_EQ(message_of([&] {
              write_file_atomic(file, [](std::ostream& out) {
                out << std::string(200'000, 'x');  // past the buffer: bytes reach the temporary
                throw Error("stopped on purpose");
              });
            }),
            "stopped on purpose");
  EXPECT_EQ(read(file), "old contents");
  EXPECT_TRUE(temporaries().empty());
  // Any other exception becomes a sylva::Error naming the path.
  const std::string wrapped =
      message_of([&] { write_file_atomic(file, [](std::ostream&) { throw std::runtime_error("disk on fire"); }); });
  EXPECT_EQ(wrapped, file.string() + ": disk on fire");
  EXPECT_EQ(read(file), "old contents");
  // The same for writers by name, which may have written the temporary.
  EXPECT_THROW(write_file_atomic_by_name(file,
                                         [](const fs::path& temp) {
                                           put(temp, "half");
                                           throw Error("library failed");
                                         }),
               Error);
  EXPECT_EQ(read(file), "old contents");
  EXPECT_TRUE(temporaries().empty());
  // A writer that never creates the target leaves no target either.
  const fs::path fresh = dir_ / "never.txt";
  EXPECT_THROW(write_file_atomic(fresh, [](std::ostream&) { throw Error("no"); }), Error);
  EXPECT_FALSE(fs::exists(fresh));
}

TEST_F(AtomicFile, ErrorsNameThePath) {
  const fs::path missing = dir_ / "no" / "such" / "dir" / "out.txt";
  const std::string m = message_of([&] { write_file_atomic(missing, [](std::ostream& out) { out << "x"; }); });
  EXPECT_EQ(m.rfind(missing.string() + ": ", 0), 0u) << m;
  EXPECT_FALSE(fs::exists(missing));

  // The target is a directory: the temporary is written, the rename fails, the temporary goes away.
  const fs::path target = dir_ / "is_a_dir";
  fs::create_directories(target / "child");
  const std::string r = message_of([&] { write_file_atomic(target, [](std::ostream& out) { out << "x"; }); });
  EXPECT_EQ(r.rfind(target.string() + ": ", 0), 0u) << r;
  EXPECT_TRUE(fs::is_directory(target / "child"));
  EXPECT_TRUE(temporaries().empty());
}

TEST_F(AtomicFile, FailedStreamIsReportedAndCleanedUp) {
  // A stream that went bad (as on a full disk) aborts the write.
  const fs::path file = dir_ / "bad_stream.txt";
  put(file, "old");
  const std::string m = message_of([&] {
    write_file_atomic(file, [](std::ostream& out) {
      out << "partial";
      out.setstate(std::ios::badbit);
    });
  });
  EXPECT_EQ(m.rfind(file.string() + ": cannot write", 0), 0u) << m;
  EXPECT_EQ(read(file), "old");
  EXPECT_TRUE(temporaries().empty());
}

TEST_F(AtomicFile, LongFileNamesWork) {
  // A 250-byte name: "<name>.tmp-<pid>" would pass the 255-byte limit of most file systems.
  const fs::path file = dir_ / (std::string(246, 'n') + ".txt");
  ASSERT_EQ(file.filename().string().size(), 250u);
  write_file_atomic(file, [](std::ostream& out) { out << "long"; });
  EXPECT_EQ(read(file), "long");
  write_file_atomic_by_name(file, [](const fs::path& temp) { put(temp, "by name"); });
  EXPECT_EQ(read(file), "by name");
  EXPECT_TRUE(temporaries().empty());
}

TEST_F(AtomicFile, ByNameCommitsWhatTheLibraryWrote) {
  const fs::path file = dir_ / "image.exr";
  fs::path seen;
  write_file_atomic_by_name(file, [&](const fs::path& temp) {
    seen = temp;
    EXPECT_EQ(temp.parent_path(), dir_);  // same directory, so the rename is atomic
    EXPECT_TRUE(fs::exists(temp));
    EXPECT_EQ(fs::file_size(temp), 0u);
    std::FILE* f = std::fopen(temp.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("written by name", f);
    std::fclose(f);
  });
  EXPECT_EQ(read(file), "written by name");
  EXPECT_FALSE(fs::exists(seen));
  // A relative target (no directory part) works too.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  write_file_atomic_by_name("relative.txt", [](const fs::path& temp) { put(temp, "here"); });
  fs::current_path(cwd);
  EXPECT_EQ(read(dir_ / "relative.txt"), "here");
}

TEST_F(AtomicFile, ConcurrentWritersLeaveOneCompleteFile) {
  // Threads race to write the same target, each a different large content; the survivor must be
  // exactly one writer's bytes, and every temporary must be gone.
  const fs::path file = dir_ / "contested.bin";
  constexpr int kWriters = 8;
  constexpr size_t kBytes = 400'000;
  std::vector<std::thread> threads;
  std::vector<std::string> errors(kWriters);
  for (int w = 0; w < kWriters; ++w)
    threads.emplace_back([&, w] {
      try {
        for (int round = 0; round < 5; ++round)
          write_file_atomic(file, [&](std::ostream& out) {
            for (size_t i = 0; i < kBytes; i += 1000) out << std::string(1000, static_cast<char>('A' + w));
          });
      } catch (const Error& e) {
        errors[static_cast<size_t>(w)] = e.what();
      }
    });
  for (std::thread& t : threads) t.join();
  for (const std::string& e : errors) EXPECT_EQ(e, "");
  const std::string bytes = read(file);
  ASSERT_EQ(bytes.size(), kBytes);
  EXPECT_EQ(bytes.find_first_not_of(bytes[0]), std::string::npos) << "mixed contents";
  EXPECT_GE(bytes[0], 'A');
  EXPECT_LT(bytes[0], 'A' + kWriters);
  EXPECT_TRUE(temporaries().empty());
}

}  // namespace
}  // namespace sylva

namespace sylva {
namespace {

// Issue 16: a symlinked target is written through (the link stays, the file it names is replaced);
// a FIFO or device target is refused, not replaced by a regular file.
TEST_F(AtomicFile, SymlinkedTargetIsWrittenThrough) {
  fs::create_directory(dir_ / "real");
  put(dir_ / "real" / "out.txt", "old");
  fs::create_symlink(dir_ / "real" / "out.txt", dir_ / "link.txt");
  write_file_atomic(dir_ / "link.txt", [](std::ostream& out) { out << "new"; });
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.txt"));
  EXPECT_EQ(read(dir_ / "real" / "out.txt"), "new");
  EXPECT_TRUE(temporaries().empty());
  EXPECT_TRUE(test::atomic_temporaries_in(dir_ / "real").empty());
}

TEST_F(AtomicFile, NonRegularTargetIsRefusedAndKept) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  const std::string msg = message_of([&] { write_file_atomic(dir_ / "fifo", [](std::ostream& out) { out << "x"; }); });
  EXPECT_NE(msg.find("exists and is not a regular file"), std::string::npos) << msg;
  EXPECT_TRUE(fs::is_fifo(dir_ / "fifo"));
  fs::create_directory(dir_ / "sub");
  EXPECT_THROW(write_file_atomic_by_name(dir_ / "sub", [](const fs::path&) {}), Error);
  EXPECT_TRUE(fs::is_directory(dir_ / "sub"));
  EXPECT_TRUE(temporaries().empty());
}

}  // namespace
}  // namespace sylva

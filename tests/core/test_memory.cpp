// The pages the process's memory lives in (core/memory.h).

#include "core/memory.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gnu/libc-version.h>

namespace sylva {
namespace {

TEST(HugePages, TunableAddedUnlessAlreadySet) {
  EXPECT_EQ(tunables_with_huge_pages(""), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(tunables_with_huge_pages("glibc.malloc.tcache_count=0"),
            "glibc.malloc.tcache_count=0:glibc.malloc.hugetlb=1");
  // The user's own choice, wherever it sits in the list, wins.
  EXPECT_EQ(tunables_with_huge_pages("glibc.malloc.hugetlb=0"), "");
  EXPECT_EQ(tunables_with_huge_pages("glibc.malloc.hugetlb=1"), "");
  EXPECT_EQ(tunables_with_huge_pages("glibc.malloc.arena_max=2:glibc.malloc.hugetlb=2"), "");
  // A name that only ends like it is another tunable.
  EXPECT_EQ(tunables_with_huge_pages("x.glibc.malloc.hugetlb=0"), "x.glibc.malloc.hugetlb=0:glibc.malloc.hugetlb=1");
}

// Runs the probe (tests/core/huge_pages_probe.cpp: use_huge_pages, then a 64 MiB block from
// malloc) with the given environment prefix; its output.
std::string run_probe(const std::string& environment) {
  const std::string command = "env -u GLIBC_TUNABLES -u SYLVA_HUGE_PAGES " + environment + " " + SYLVA_HUGE_PAGES_PROBE;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {};
  std::string out;
  std::array<char, 512> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe)) out += buffer.data();
  EXPECT_EQ(pclose(pipe), 0) << command;
  return out;
}

TEST(HugePages, TheProgramRunsAgainWithMallocAdvisingHugePages) {
  std::ifstream modes_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(modes_file, modes);
  int major = 0, minor = 0;
  ASSERT_EQ(std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor), 2);
  const bool applies = modes.find("[madvise]") != std::string::npos && (major > 2 || minor >= 35);

  const std::string on = run_probe("");
  EXPECT_EQ(on.find("tunables=glibc.malloc.hugetlb=1\n") != std::string::npos, applies) << on;
  // The kernel's flag "hg": malloc advised the block (whether or not 2 MiB pages were free).
  EXPECT_EQ(on.find(" hg") != std::string::npos, applies) << on;

  const std::string off = run_probe("SYLVA_HUGE_PAGES=0");
  EXPECT_NE(off.find("tunables=\n"), std::string::npos) << off;
  EXPECT_EQ(off.find(" hg"), std::string::npos) << off;

  // The user's setting is kept as it is.
  const std::string own = run_probe("GLIBC_TUNABLES=glibc.malloc.hugetlb=0");
  EXPECT_NE(own.find("tunables=glibc.malloc.hugetlb=0\n"), std::string::npos) << own;
  EXPECT_EQ(own.find(" hg"), std::string::npos) << own;
}

TEST(HugePages, ResidentMemoryIsReported) {
  const ResidentMemory m = resident_memory();
  EXPECT_GT(m.bytes, uint64_t(1) << 20);
  EXPECT_LE(m.huge_page_bytes, m.bytes);
}

}  // namespace
}  // namespace sylva

// For test_memory.cpp: asks for huge pages as the entry points do, then prints GLIBC_TUNABLES and
// the kernel's flags (VmFlags in /proc/self/smaps) of the mapping holding a fresh 64 MiB block.

#include "core/memory.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

int main(int, char** argv) {
  sylva::use_huge_pages(argv);
  const size_t bytes = size_t(64) << 20;
  char* block = static_cast<char*>(std::malloc(bytes));
  if (!block) return 1;
  std::memset(block, 1, bytes);
  const auto address = reinterpret_cast<uintptr_t>(block + bytes / 2);
  std::ifstream smaps("/proc/self/smaps");
  std::string line, flags;
  bool inside = false;
  while (std::getline(smaps, line)) {
    unsigned long lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find(':') > line.find(' '))
      inside = lo <= address && address < hi;
    else if (inside && line.rfind("VmFlags:", 0) == 0)
      flags = line;
  }
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::printf("tunables=%s\nflags=%s\n", tunables ? tunables : "", flags.c_str());
  std::free(block);
  return flags.empty() ? 1 : 0;
}

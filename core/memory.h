#pragma once
// How much memory this process may still use, for refusing work that cannot fit before it starts
// (docs/limits.md), and the pages its memory lives in.

#include <cstdint>
#include <string>
#include <string_view>

namespace sylva {

// The smallest of: the system's available memory (MemAvailable in /proc/meminfo), the address-space
// limit (RLIMIT_AS, `ulimit -v`) less the process's current virtual size, and the cgroup v2
// memory.max less memory.current. UINT64_MAX when none of them can be read.
uint64_t available_memory_bytes();

// Transparent huge pages (2 MiB) for everything the process allocates: the scene's arrays, Embree's
// BVH and buffers, the film. A BVH walk over hundreds of MiB in 4 KiB pages misses the TLB at
// nearly every node; in 2 MiB pages the forest renders about 5 % faster and loads faster (fewer
// page faults), for about 3 % more peak memory (bench/README.md, "Huge pages").
//
// Debian's kernels give them only to memory advised for them (THP mode "madvise"), and glibc's
// malloc advises its memory only under the tunable glibc.malloc.hugetlb=1 (glibc 2.35 on), read
// once when the process starts. So the entry points call this first: where the kernel's mode is
// "madvise" and glibc knows the tunable, it adds it to GLIBC_TUNABLES and executes the program
// again (about 20 ms, once). It returns without doing anything when the tunable is already set
// (the user's choice wins), when SYLVA_HUGE_PAGES=0, under Valgrind, or when executing fails.
void use_huge_pages(char** argv);

// GLIBC_TUNABLES with glibc.malloc.hugetlb=1 added to `current`; empty when `current` already
// sets glibc.malloc.hugetlb.
std::string tunables_with_huge_pages(std::string_view current);

// Of the process's memory now: resident bytes, and how many of them are in transparent huge pages
// (/proc/self/smaps_rollup; zeros where it cannot be read).
struct ResidentMemory {
  uint64_t bytes = 0, huge_page_bytes = 0;
};
ResidentMemory resident_memory();

}  // namespace sylva

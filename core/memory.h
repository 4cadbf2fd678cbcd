#pragma once
// How much memory this process may still use, for refusing work that cannot fit before it starts
// (docs/limits.md).

#include <cstdint>

namespace sylva {

// The smallest of: the system's available memory (MemAvailable in /proc/meminfo), the address-space
// limit (RLIMIT_AS, `ulimit -v`) less the process's current virtual size, and the cgroup v2
// memory.max less memory.current. UINT64_MAX when none of them can be read.
uint64_t available_memory_bytes();

}  // namespace sylva

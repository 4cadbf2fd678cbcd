#include "core/memory.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/resource.h>

namespace sylva {

namespace {

// The number after `key` in a "key: value kB" file such as /proc/meminfo, in bytes; 0 if absent.
uint64_t kilobytes_field(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      std::istringstream fields(line.substr(key.size()));
      uint64_t kb = 0;
      fields >> kb;
      return kb * 1024;
    }
  return 0;
}

// A cgroup v2 file holding one number (or "max"); UINT64_MAX if absent or "max".
uint64_t cgroup_number(const char* name) {
  std::ifstream in(std::string("/sys/fs/cgroup/") + name);
  std::string text;
  if (!(in >> text) || text == "max") return UINT64_MAX;
  try {
    return std::stoull(text);
  } catch (const std::exception&) {
    return UINT64_MAX;
  }
}

}  // namespace

uint64_t available_memory_bytes() {
  uint64_t available = UINT64_MAX;
  if (const uint64_t mem = kilobytes_field("/proc/meminfo", "MemAvailable:"); mem > 0) available = mem;
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const uint64_t used = kilobytes_field("/proc/self/status", "VmSize:");
    const uint64_t cap = static_cast<uint64_t>(limit.rlim_cur);
    available = std::min(available, cap > used ? cap - used : 0);
  }
  const uint64_t cg_max = cgroup_number("memory.max"), cg_current = cgroup_number("memory.current");
  if (cg_max != UINT64_MAX && cg_current != UINT64_MAX)
    available = std::min(available, cg_max > cg_current ? cg_max - cg_current : 0);
  return available;
}

}  // namespace sylva

#include "core/memory.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include <gnu/libc-version.h>
#include <sys/resource.h>
#include <unistd.h>

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

// Whether glibc, as loaded, reads the tunable glibc.malloc.hugetlb (2.35 on).
bool glibc_has_hugetlb_tunable() {
  int major = 0, minor = 0;
  return std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor) == 2 &&
         (major > 2 || (major == 2 && minor >= 35));
}

// Whether the kernel gives transparent huge pages to advised memory only ("[madvise]" selected).
bool thp_on_advice_only() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(in, modes);
  return modes.find("[madvise]") != std::string::npos;
}

}  // namespace

std::string tunables_with_huge_pages(std::string_view current) {
  // GLIBC_TUNABLES is a colon-separated list of name=value.
  size_t start = 0;
  while (start <= current.size()) {
    const size_t end = std::min(current.find(':', start), current.size());
    if (current.substr(start, end - start).starts_with("glibc.malloc.hugetlb=")) return {};
    start = end + 1;
  }
  return current.empty() ? std::string("glibc.malloc.hugetlb=1") : std::string(current) + ":glibc.malloc.hugetlb=1";
}

void use_huge_pages(char** argv) {
  if (const char* choice = std::getenv("SYLVA_HUGE_PAGES"); choice && std::strcmp(choice, "0") == 0) return;
  // Under Valgrind the program executed again would run outside it (without --trace-children).
  if (const char* preload = std::getenv("LD_PRELOAD"); preload && std::strstr(preload, "vgpreload")) return;
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string current = set ? set : "";
  const std::string tunables = tunables_with_huge_pages(current);
  if (tunables.empty() || !glibc_has_hugetlb_tunable() || !thp_on_advice_only()) return;
  if (::setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // Not executed (no /proc, say): go on in 4 KiB pages, and put the environment back for children.
  if (set)
    ::setenv("GLIBC_TUNABLES", current.c_str(), 1);
  else
    ::unsetenv("GLIBC_TUNABLES");
}

ResidentMemory resident_memory() {
  return {kilobytes_field("/proc/self/smaps_rollup", "Rss:"),
          kilobytes_field("/proc/self/smaps_rollup", "AnonHugePages:")};
}

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

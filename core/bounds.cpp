#include "core/bounds.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>

namespace colony {

uint64_t AvailableMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  uint64_t bytes = pages > 0 && page > 0
                       ? static_cast<uint64_t>(pages) * static_cast<uint64_t>(page)
                       : UINT64_MAX;
  // cgroup v2 ("max" when unlimited), then v1.
  for (const char* path :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(path);
    uint64_t limit = 0;
    if (in >> limit && limit > 0) bytes = std::min(bytes, limit);
  }
  return bytes;
}

std::string FormatBytes(double bytes) {
  char buffer[32];
  if (bytes >= 1e12) {
    std::snprintf(buffer, sizeof buffer, "%.0f GB", bytes / 1e9);
  } else if (bytes >= 1e9) {
    std::snprintf(buffer, sizeof buffer, "%.3g GB", bytes / 1e9);
  } else if (bytes >= 1e6) {
    std::snprintf(buffer, sizeof buffer, "%.3g MB", bytes / 1e6);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.3g kB", bytes / 1e3);
  }
  return buffer;
}

}  // namespace colony

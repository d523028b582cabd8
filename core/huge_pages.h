#pragma once
// Transparent huge pages for the large arrays of big swarms.
//
// At a million robots a load first touches over a gigabyte, and in 4 KB
// pages that is some 300,000 page faults and as many TLB entries for arrays
// that are then read in random order (the id table, the placement grid).
// The kernel backs a range with 2 MB pages when asked (madvise
// MADV_HUGEPAGE; /sys/kernel/mm/transparent_hugepage/enabled set to
// "madvise" or "always"). Only whole 2 MB pages inside the range are
// advised, so arrays smaller than that, e.g. those of a 10,000-robot
// scene, are left as they are (and their resident set does not grow). A
// hint: where the kernel declines, nothing changes.
#include <cstddef>
#include <vector>

namespace colony {

void AdviseHugePages(const void* data, size_t bytes);

// The vector's whole capacity (call it after reserve and before filling).
template <class T>
void AdviseHugePages(const std::vector<T>& v) {
  AdviseHugePages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace colony

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
//
// Prefault::kInBackground also has the kernel map those whole pages in
// (madvise MADV_POPULATE_WRITE, Linux 5.14 and later) on a thread of its own
// while the caller goes on filling the array: the zeroing of fresh pages
// then happens beside the load instead of in its page faults, and populating
// a range costs the kernel less than faulting it in piece by piece (four
// interleaved runs of `colony_bench diffusion_1000000.xml --ticks 1`: 1.2 to
// 1.9 s of system time before, 0.5 to 1.0 s after). It never changes what
// the memory holds (the kernel maps pages, it writes no data), so a range
// freed or refilled in the meantime is harmless. Only for arrays that will
// be filled whole: it makes the range resident. The thread exists while
// there is work; it uses a core even in a run on one thread.
#include <cstddef>
#include <vector>

namespace colony {

enum class Prefault { kNo, kInBackground };

void AdviseHugePages(const void* data, size_t bytes, Prefault prefault = Prefault::kNo);

// The vector's whole capacity (call it after reserve and before filling).
template <class T>
void AdviseHugePages(const std::vector<T>& v, Prefault prefault = Prefault::kNo) {
  AdviseHugePages(v.data(), v.capacity() * sizeof(T), prefault);
}

// Waits until every range asked for so far is populated (or refused).
void WaitForBackgroundPrefaults();

}  // namespace colony

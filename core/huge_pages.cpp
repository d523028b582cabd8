#include "core/huge_pages.h"

#include <sys/mman.h>

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <thread>
#include <utility>

namespace colony {
namespace {

constexpr uintptr_t kHuge = uintptr_t{2} << 20;

// The ranges waiting to be populated and whether a thread is at them. Made
// once and never destroyed: the thread is detached and may still be
// finishing while the process exits.
struct Prefaulter {
  std::mutex mutex;
  std::condition_variable idle;
  std::deque<std::pair<uintptr_t, uintptr_t>> work;
  bool running = false;
};

Prefaulter& ThePrefaulter() {
  static Prefaulter* const prefaulter = new Prefaulter;
  return *prefaulter;
}

void PopulateQueued() {
  Prefaulter& p = ThePrefaulter();
  for (;;) {
    std::pair<uintptr_t, uintptr_t> range;
    {
      std::lock_guard<std::mutex> lock(p.mutex);
      if (p.work.empty()) {
        p.running = false;
        p.idle.notify_all();
        return;
      }
      range = p.work.front();
      p.work.pop_front();
    }
    // A huge page at a time, so that the pages the caller reaches first are
    // there first. A refusal (an older kernel, a range freed meanwhile) ends
    // this range: the caller's own faults map it as before.
    for (uintptr_t at = range.first; at < range.second; at += kHuge) {
      if (madvise(reinterpret_cast<void*>(at), std::min(kHuge, range.second - at),
                  MADV_POPULATE_WRITE) != 0) {
        break;
      }
    }
  }
}

}  // namespace

void AdviseHugePages(const void* data, size_t bytes, Prefault prefault) {
  const uintptr_t at = reinterpret_cast<uintptr_t>(data);
  const uintptr_t begin = (at + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = (at + bytes) & ~(kHuge - 1);
  if (end <= begin) return;
  // A hint: its failure (no THP in this kernel) changes nothing but speed.
  (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  if (prefault != Prefault::kInBackground) return;
  Prefaulter& p = ThePrefaulter();
  std::lock_guard<std::mutex> lock(p.mutex);
  p.work.emplace_back(begin, end);
  if (!p.running) {
    p.running = true;
    std::thread(PopulateQueued).detach();
  }
}

void WaitForBackgroundPrefaults() {
  Prefaulter& p = ThePrefaulter();
  std::unique_lock<std::mutex> lock(p.mutex);
  p.idle.wait(lock, [&] { return !p.running; });
}

}  // namespace colony

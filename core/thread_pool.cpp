#include "core/thread_pool.h"

#include <algorithm>

#include "core/crash_report.h"

namespace colony {

ThreadPool::ThreadPool(int threads) : threads_(std::max(threads, 0)) {
  for (int i = 1; i < threads_; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

// Takes chunks until none is left; the mutex is held on entry and exit.
namespace {
// Set while a thread runs a chunk: a ParallelFor called from inside one
// (an engine stepping in parallel with other engines) runs inline.
thread_local bool t_in_job = false;
}  // namespace

void ThreadPool::RunChunks() {
  std::unique_lock lock(mutex_, std::adopt_lock);
  while (next_ < n_) {
    const size_t begin = next_;
    const size_t end = std::min(n_, begin + chunk_);
    next_ = end;
    ++pending_;
    const auto* job = job_;
    lock.unlock();
    t_in_job = true;
    (*job)(begin, end);
    t_in_job = false;
    lock.lock();
    if (--pending_ == 0 && next_ >= n_) done_.notify_all();
  }
  lock.release();
}

void ThreadPool::WorkerLoop() {
  UseAlternateSignalStack();
  uint64_t seen = 0;
  mutex_.lock();
  while (true) {
    {
      std::unique_lock lock(mutex_, std::adopt_lock);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      lock.release();
    }
    if (stop_) {
      mutex_.unlock();
      return;
    }
    seen = generation_;
    RunChunks();
  }
}

void ThreadPool::ParallelFor(size_t n, size_t min_chunk, ChunkFn fn) {
  if (n == 0) return;
  min_chunk = std::max<size_t>(min_chunk, 1);
  if (workers_.empty() || n <= min_chunk || t_in_job) {
    fn(0, n);
    return;
  }
  // Many chunks per thread (16) balance uneven work: every phase of a tick
  // ends at this barrier, and with few large chunks one thread sat idle for
  // up to a chunk at each of them. Taking a chunk costs one lock.
  // A whole number of min_chunk (the nearest to that aim): every chunk starts
  // at a multiple of it, so items grouped by that many (the robots sharing a
  // Lua state) are always run by one thread, in order.
  const size_t aim = (n + threads_ * 16 - 1) / (threads_ * 16);
  const size_t chunk = std::max<size_t>(1, (aim + min_chunk / 2) / min_chunk) * min_chunk;
  std::unique_lock lock(mutex_);
  job_ = &fn;
  n_ = n;
  chunk_ = chunk;
  next_ = 0;
  pending_ = 0;
  ++generation_;
  wake_.notify_all();
  lock.release();
  RunChunks();
  lock = std::unique_lock(mutex_, std::adopt_lock);
  done_.wait(lock, [&] { return next_ >= n_ && pending_ == 0; });
  job_ = nullptr;
  n_ = 0;
}

}  // namespace colony

#include "core/thread_pool.h"

#include <algorithm>
#include <chrono>

#include "core/crash_report.h"

namespace colony {

ThreadPool::ThreadPool(int threads)
    : threads_(std::max(threads, 0)),
      spin_(static_cast<unsigned>(threads_) <= std::thread::hardware_concurrency()) {
  shares_.resize(std::max(threads_, 1));
  for (int i = 1; i < threads_; ++i) workers_.emplace_back([this, i] { WorkerLoop(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_.store(true, std::memory_order_relaxed);
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

namespace {
// Waits up to kSpin for done() to become true, without the mutex and without
// sleeping; returns whether it did. A tick is a row of short ParallelFor jobs
// with some serial work between them. A worker put to sleep on the condition
// variable between two of them took 36 us on average to start on the next
// (diffusion, 10,000 robots, two threads: 109 ms of a 1.45 s run, while the
// caller worked alone), and the caller slept as long waiting for the last
// chunk. Spinning 400 us covers nearly every gap of such a tick (the workers
// then start within 1 us). Only when the pool has no more threads than the
// machine; and every 64 pauses (about a microsecond) the spinning thread
// yields, so that other programs' threads waiting for a core (another
// simulation, a test run beside it) get it rather than watch it spin.
constexpr auto kSpin = std::chrono::microseconds(400);
template <class Done>
bool SpinUntil(Done&& done) {
  if (done()) return true;
  const auto until = std::chrono::steady_clock::now() + kSpin;
  while (true) {
    for (int i = 0; i < 64; ++i) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
      if (done()) return true;
    }
    if (std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::yield();
  }
}

// Set while a thread runs a chunk: a ParallelFor called from inside one
// (an engine stepping in parallel with other engines) runs inline.
thread_local bool t_in_job = false;
}  // namespace

// Takes chunks until none is left, its own share first; the mutex is held on
// entry and exit.
void ThreadPool::RunChunks(int home) {
  std::unique_lock lock(mutex_, std::adopt_lock);
  while (left_ > 0) {
    Share* from = &shares_[home];
    if (from->front == from->back) {
      for (Share& s : shares_) {
        if (s.back - s.front > from->back - from->front) from = &s;
      }
    }
    const size_t c = from == &shares_[home] ? from->front++ : --from->back;
    --left_;
    const size_t begin = c * chunk_;
    const size_t end = std::min(n_, begin + chunk_);
    pending_.fetch_add(1, std::memory_order_relaxed);
    const auto* job = job_;
    lock.unlock();
    t_in_job = true;
    (*job)(begin, end);
    t_in_job = false;
    lock.lock();
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1 && left_ == 0) done_.notify_all();
  }
  lock.release();
}

void ThreadPool::WorkerLoop(int home) {
  UseAlternateSignalStack();
  uint64_t seen = 0;
  while (true) {
    if (spin_) {
      SpinUntil([&] {
        return generation_.load(std::memory_order_acquire) != seen ||
               stop_.load(std::memory_order_relaxed);
      });
    }
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] {
        return stop_.load(std::memory_order_relaxed) ||
               generation_.load(std::memory_order_relaxed) != seen;
      });
      lock.release();
    }
    if (stop_.load(std::memory_order_relaxed)) {
      mutex_.unlock();
      return;
    }
    seen = generation_.load(std::memory_order_relaxed);
    ++waits_.worker_starts;
    waits_.worker_start_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - job_start_).count();
    RunChunks(home);
    mutex_.unlock();
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
  const size_t chunks = (n + chunk - 1) / chunk;
  left_ = chunks;
  for (size_t t = 0; t < shares_.size(); ++t) {
    shares_[t] = {t * chunks / shares_.size(), (t + 1) * chunks / shares_.size()};
  }
  ++waits_.jobs;
  job_start_ = std::chrono::steady_clock::now();
  pending_.store(0, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  wake_.notify_all();
  lock.release();
  RunChunks(0);
  // Every chunk is taken (RunChunks returns when none is left): wait for the
  // ones other threads are still running.
  const auto wait_start = std::chrono::steady_clock::now();
  if (spin_ && pending_.load(std::memory_order_acquire) != 0) {
    mutex_.unlock();
    SpinUntil([&] { return pending_.load(std::memory_order_acquire) == 0; });
    mutex_.lock();
  }
  lock = std::unique_lock(mutex_, std::adopt_lock);
  done_.wait(lock, [&] { return pending_.load(std::memory_order_relaxed) == 0; });
  waits_.caller_wait_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wait_start).count();
  job_ = nullptr;
  n_ = 0;
}

ThreadPool::Waits ThreadPool::waits() {
  std::lock_guard lock(mutex_);
  return waits_;
}

void ThreadPool::ResetWaits() {
  std::lock_guard lock(mutex_);
  waits_ = {};
}

}  // namespace colony

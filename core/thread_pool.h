// The thread pool used for physics and for sense + control. ParallelFor splits
// [0, n) into chunks; callers write only per-index data, so results do not
// depend on the number of threads or on scheduling.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace colony {

// A borrowed callable fn(begin, end): two pointers, made without allocating
// (a std::function holding a lambda that captures more than two references
// allocates, and a tick calls ParallelFor several times). It refers to the
// callable it was made from, which must outlive it: pass it straight to
// ParallelFor, which returns when every chunk is done.
class ChunkFn {
 public:
  template <class F>
  requires(!std::is_same_v<std::remove_cvref_t<F>, ChunkFn>)
      ChunkFn(F&& f)  // NOLINT(google-explicit-constructor): lambdas convert implicitly
      : object_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
        call_([](void* object, size_t begin, size_t end) {
          (*static_cast<std::remove_reference_t<F>*>(object))(begin, end);
        }) {}
  void operator()(size_t begin, size_t end) const { call_(object_, begin, end); }

 private:
  void* object_;
  void (*call_)(void*, size_t, size_t);
};

// A thread's working memory for a chunk: the value kept for this thread
// (by type and Tag) since its last chunk, so that a warm step does not
// allocate, moved into this object for the chunk's length and back at its
// end. Declare one at the top of a chunk. In a shared library every use of a
// thread_local calls __tls_get_addr, and the compiler may repeat that call
// where it could have kept the address: this object is a local.
template <class T, class Tag = void>
class ChunkScratch {
 public:
  ChunkScratch() : value_(std::move(Kept())) {}
  ~ChunkScratch() { Kept() = std::move(value_); }
  ChunkScratch(const ChunkScratch&) = delete;
  ChunkScratch& operator=(const ChunkScratch&) = delete;
  T& operator*() { return value_; }
  T* operator->() { return &value_; }

 private:
  static T& Kept() {
    static thread_local T kept;
    return kept;
  }
  T value_;
};

class ThreadPool {
 public:
  // threads <= 1: everything runs on the calling thread. Otherwise the caller
  // works alongside threads - 1 workers.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return threads_; }
  // Calls fn(begin, end) over chunks of [0, n) of at least `min_chunk` items,
  // each starting at a multiple of `min_chunk`.
  // Called from inside a chunk, it runs everything inline.
  void ParallelFor(size_t n, size_t min_chunk, ChunkFn fn);

  // Time the threads spent waiting on each other in the jobs shared with
  // workers (ParallelFor calls that did not run inline), since construction
  // or the last ResetWaits. Call from the thread that calls ParallelFor.
  struct Waits {
    uint64_t jobs = 0;
    uint64_t worker_starts = 0;  // a worker taking up a job
    double worker_start_s = 0;   // summed: from a job's start to a worker taking it up
    double caller_wait_s = 0;    // the caller waiting for the last chunks other threads ran
  };
  Waits waits();
  void ResetWaits();

 private:
  void WorkerLoop(int home);
  void RunChunks(int home);

  int threads_;
  bool spin_;  // wait by spinning briefly before sleeping (not when oversubscribed)
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const ChunkFn* job_ = nullptr;
  size_t n_ = 0, chunk_ = 0, left_ = 0;  // left_: chunks not yet taken
  // Each thread's share of a job's chunks (the caller's is the first, worker
  // k's the k+1st), [front, back): a thread takes its own from the front and,
  // when they are gone, another's from the back. Jobs over the same items
  // follow each other in a tick (sense + control, the actuators, the engine's
  // passes), so each thread mostly gets the same items again, still in its
  // cache, rather than whichever the other thread wrote last.
  struct Share {
    size_t front = 0, back = 0;
  };
  std::vector<Share> shares_;
  // Changed under the mutex; read without it by threads spinning for them.
  std::atomic<size_t> pending_ = 0;  // chunks being run
  std::atomic<uint64_t> generation_ = 0;
  std::atomic<bool> stop_ = false;
  // Waits, under the mutex.
  std::chrono::steady_clock::time_point job_start_;
  Waits waits_;
};

}  // namespace colony

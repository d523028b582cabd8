// ThreadPool::ParallelFor: every index exactly once, whatever the number of
// threads, items and chunk size. Suites are named core_test_* so
// `ctest -R core_test` selects them.
#include "core/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <set>
#include <thread>
#include <utility>
#include <vector>

namespace colony {
namespace {

TEST(core_test_thread_pool, ThreadCount) {
  EXPECT_EQ(ThreadPool(0).threads(), 0);
  EXPECT_EQ(ThreadPool(1).threads(), 1);
  EXPECT_EQ(ThreadPool(4).threads(), 4);
  EXPECT_EQ(ThreadPool(-3).threads(), 0);
}

TEST(core_test_thread_pool, EveryIndexExactlyOnce) {
  for (int threads : {0, 1, 2, 4}) {
    ThreadPool pool(threads);
    for (size_t n : {0, 1, 2, 3, 7, 64, 100, 1000, 10007}) {
      for (size_t min_chunk : {0, 1, 16, 64}) {
        std::unique_ptr<std::atomic<int>[]> counts(new std::atomic<int>[n + 1]);
        for (size_t i = 0; i <= n; ++i) counts[i] = 0;
        std::atomic<int> calls = 0;
        pool.ParallelFor(n, min_chunk, [&](size_t begin, size_t end) {
          ++calls;
          EXPECT_LT(begin, end);
          EXPECT_LE(end, n);
          for (size_t i = begin; i < end; ++i) ++counts[i];
        });
        if (n == 0) {
          EXPECT_EQ(calls.load(), 0) << "nothing to do: no call";
        }
        for (size_t i = 0; i < n; ++i) {
          ASSERT_EQ(counts[i].load(), 1) << "index " << i << " of " << n << ", threads " << threads
                                         << ", min_chunk " << min_chunk;
        }
        EXPECT_EQ(counts[n].load(), 0) << "no index past the end";
      }
    }
  }
}

TEST(core_test_thread_pool, ChunksHoldAtLeastMinChunkItems) {
  for (int threads : {0, 1, 2, 4}) {
    ThreadPool pool(threads);
    std::mutex mutex;
    std::vector<std::pair<size_t, size_t>> chunks;
    pool.ParallelFor(1000, 64, [&](size_t begin, size_t end) {
      std::lock_guard lock(mutex);
      chunks.emplace_back(begin, end);
    });
    for (const auto& [begin, end] : chunks) {
      if (end != 1000) {
        EXPECT_GE(end - begin, 64u) << "threads " << threads;
      }
    }
  }
}

TEST(core_test_thread_pool, OneThreadRunsOnTheCaller) {
  for (int threads : {0, 1}) {
    ThreadPool pool(threads);
    std::set<std::thread::id> ids;
    pool.ParallelFor(1000, 1, [&](size_t, size_t) { ids.insert(std::this_thread::get_id()); });
    EXPECT_EQ(ids, std::set<std::thread::id>{std::this_thread::get_id()});
  }
}

TEST(core_test_thread_pool, ManySmallJobsInARow) {
  // Back-to-back calls, as in a simulation's ticks: no index lost or repeated
  // across jobs, no hang.
  ThreadPool pool(4);
  std::vector<int> totals(5000, 0);
  for (size_t job = 0; job < totals.size(); ++job) {
    const size_t n = job % 13;
    std::atomic<int> sum = 0;
    pool.ParallelFor(n, 1, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) sum += static_cast<int>(i) + 1;
    });
    totals[job] = sum;
    ASSERT_EQ(totals[job], static_cast<int>(n * (n + 1) / 2)) << "job " << job;
  }
}

TEST(core_test_thread_pool, JobsAfterIdlePauses) {
  // Workers wait for the next job spinning for a moment, then asleep: jobs
  // that come right away, after a short pause and after a long one (longer
  // than the spin) all run every index once.
  for (int threads : {2, 4}) {
    ThreadPool pool(threads);
    for (int job = 0; job < 12; ++job) {
      std::this_thread::sleep_for(std::chrono::microseconds(job % 3 == 0   ? 0
                                                            : job % 3 == 1 ? 50
                                                                           : 2000));
      std::vector<std::atomic<int>> counts(257);
      pool.ParallelFor(counts.size(), 1, [&](size_t begin, size_t end) {
        if (begin == 0) std::this_thread::sleep_for(std::chrono::microseconds(job % 2 ? 1000 : 0));
        for (size_t i = begin; i < end; ++i) ++counts[i];
      });
      for (size_t i = 0; i < counts.size(); ++i) {
        ASSERT_EQ(counts[i].load(), 1)
            << "index " << i << ", job " << job << ", threads " << threads;
      }
    }
  }
}

TEST(core_test_thread_pool, WaitsCountTheJobsSharedWithWorkers) {
  ThreadPool alone(1);
  alone.ParallelFor(1000, 1, [](size_t, size_t) {});
  EXPECT_EQ(alone.waits().jobs, 0u) << "one thread: every job runs inline";

  ThreadPool pool(2);
  std::atomic<int> sum = 0;
  for (int job = 0; job < 5; ++job) {
    pool.ParallelFor(1000, 1, [&](size_t begin, size_t end) {
      std::this_thread::sleep_for(std::chrono::microseconds(20));
      sum += static_cast<int>(end - begin);
    });
  }
  pool.ParallelFor(3, 8, [&](size_t begin, size_t end) { sum += static_cast<int>(end - begin); });
  EXPECT_EQ(sum.load(), 5003);
  const ThreadPool::Waits waits = pool.waits();
  EXPECT_EQ(waits.jobs, 5u) << "the job of 3 items, below min_chunk, ran inline";
  EXPECT_GE(waits.worker_starts, 1u);
  EXPECT_LE(waits.worker_starts, 5u);
  EXPECT_GE(waits.worker_start_s, 0.0);
  EXPECT_GE(waits.caller_wait_s, 0.0);
  pool.ResetWaits();
  EXPECT_EQ(pool.waits().jobs, 0u);
  EXPECT_EQ(pool.waits().worker_starts, 0u);
}

TEST(core_test_thread_pool, ResultsDoNotDependOnThreadCount) {
  auto run = [](int threads) {
    ThreadPool pool(threads);
    std::vector<double> out(20000);
    pool.ParallelFor(out.size(), 8, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) out[i] = static_cast<double>(i) * 0.5 + 1.0 / (i + 1);
    });
    return out;
  };
  const auto reference = run(0);
  EXPECT_EQ(run(1), reference);
  EXPECT_EQ(run(2), reference);
  EXPECT_EQ(run(4), reference);
}

}  // namespace
}  // namespace colony

namespace {
struct OtherUser {};
}  // namespace

TEST(core_test_chunk_scratch, AThreadGetsBackWhatItsLastChunkLeftAndOthersStartEmpty) {
  {
    colony::ChunkScratch<std::vector<int>> first;
    EXPECT_TRUE(first->empty());
    first->assign(100, 7);
  }
  const int* kept = nullptr;
  {
    colony::ChunkScratch<std::vector<int>> second;
    ASSERT_EQ(second->size(), 100u);  // no allocation: the same buffer
    EXPECT_EQ((*second)[99], 7);
    kept = second->data();
  }
  {
    // Another user's kept value is its own.
    colony::ChunkScratch<std::vector<int>, OtherUser> other;
    EXPECT_TRUE(other->empty());
  }
  std::thread([] {
    colony::ChunkScratch<std::vector<int>> elsewhere;
    EXPECT_TRUE(elsewhere->empty()) << "another thread's chunk saw this thread's list";
  }).join();
  colony::ChunkScratch<std::vector<int>> again;
  EXPECT_EQ(again->data(), kept);
}

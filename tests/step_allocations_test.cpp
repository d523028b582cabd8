// Simulation::Step does not allocate once warm: every buffer a tick needs is
// sized during loading or the first ticks. This binary replaces the global
// operator new with one that counts calls (on every thread, the pool's
// workers included), then runs benchmark scenes for 10 ticks after a few warm
// ticks and expects no allocation at all (diffusion, one thread), or none but
// per-thread lists made once (two threads) or receive buffers grown (flocking).
#include <atomic>
#include <cstdlib>
#include <new>

#include "tests/test_util.h"

namespace {

std::atomic<long long> g_allocations{0};

void* CountedAllocate(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}

void* CountedAllocateAligned(std::size_t size, std::align_val_t align) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t size) { return CountedAllocate(size); }
void* operator new[](std::size_t size) { return CountedAllocate(size); }
void* operator new(std::size_t size, std::align_val_t align) {
  return CountedAllocateAligned(size, align);
}
void* operator new[](std::size_t size, std::align_val_t align) {
  return CountedAllocateAligned(size, align);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace colony {
namespace {

// Allocations made by `ticks` calls of Step after `warm` ticks of `file`.
long long AllocationsOverTicks(const std::string& file, int threads, int warm, int ticks) {
  ExperimentOptions options;
  options.file = std::string(COLONY_SOURCE_DIR "/") + file;
  options.threads = threads;
  auto sim = Simulation::Load(options);
  for (int t = 0; t < warm; ++t) sim->Step();
  const long long before = g_allocations.load();
  for (int t = 0; t < ticks; ++t) sim->Step();
  return g_allocations.load() - before;
}

TEST(StepAllocations, CounterSeesAllocations) {
  const long long before = g_allocations.load();
  auto* v = new std::vector<int>(100);
  delete v;
  EXPECT_EQ(g_allocations.load() - before, 2);
}

TEST(StepAllocations, DiffusionStepsWithoutAllocating) {
  EXPECT_EQ(AllocationsOverTicks("experiments/benchmarks/diffusion_1000.xml", 1, 5, 10), 0);
}

// With a worker thread, the neighbour lists are per thread (kept between
// ticks): a worker that happens not to run one of the two loops that use
// them (proximity, with three lists: the robot's neighbours, the next
// robot's and the footprints its rays may hit; kinematics2d, one) during the
// warm ticks, as on a loaded machine, makes its lists once later. Nothing
// else may allocate.
TEST(StepAllocations, DiffusionWithTwoThreadsAllocatesAtMostTheWorkersLists) {
  EXPECT_LE(AllocationsOverTicks("experiments/benchmarks/diffusion_1000.xml", 2, 5, 10), 4);
}

// Flocking (range-and-bearing) still allocates in a warm step, but only
// to grow a receiver's packet buffer (a std::vector in the control interface,
// sensors/range_and_bearing/range_and_bearing.h) when it hears more
// messages than ever before: the swarm keeps getting denser, about 8 growths
// per tick over 1,000 robots here. A per-robot allocation in every step would
// be 10,000 over these 10 ticks; the bound catches that, not the growth.
TEST(StepAllocations, FlockingAllocatesOnlyToGrowReceiveBuffers) {
  for (int threads : {1, 2}) {
    EXPECT_LT(AllocationsOverTicks("experiments/benchmarks/flocking_1000.xml", threads, 5, 10), 200)
        << "with " << threads << " threads";
  }
}

}  // namespace
}  // namespace colony

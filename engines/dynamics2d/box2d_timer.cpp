// Box2D 2.4's profiling timer, made free.
//
// b2World::Step times its phases, and b2Island::Solve each island's, with a
// b2Timer that reads the clock (gettimeofday) on every Reset() and
// GetMilliseconds(): six reads per island per step, and on a free floor every
// robot is an island of its own. The figures only fill b2World::GetProfile(),
// which Colony never reads, yet on a virtual machine with a slow clock the
// reads were a quarter of a dynamics2d step (diffusion_dyn2d_quadrants_10000,
// one thread: 1,909 -> 1,410 CPU ns per robot-step, the same state hash).
//
// Box2D calls its timer through the dynamic linker (libbox2d.so exports
// b2Timer and calls it through its procedure linkage table), so these
// definitions, in libcolony, are the ones every b2World in the process uses.
// b2World::GetProfile() then reads 0 for every phase; dynamics2d_test checks
// that this override is in effect.
#include <box2d/b2_timer.h>

b2Timer::b2Timer() : m_start_sec(0), m_start_usec(0) {}

void b2Timer::Reset() {}

float b2Timer::GetMilliseconds() const { return 0.0f; }

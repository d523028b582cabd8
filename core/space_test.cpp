// The space: adding and removing entities, handles that detect reuse of a
// slot, lookup by id and by type, and the spatial index behind Gather.
// Suites are named core_test_* so `ctest -R core_test` selects them.
#include "core/space.h"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/device.h"
#include "core/huge_pages.h"
#include "core/thread_pool.h"

namespace colony {
namespace {

Space::EntityInit Robot(const std::string& id, uint16_t type, double x, double y,
                        double radius = 0.1) {
  Space::EntityInit init;
  init.id = id;
  init.type = type;
  init.pose.position = Vec3(x, y, 0);
  init.geometry.shape = ShapeKind::kCylinder;
  init.geometry.radius = radius;
  init.geometry.size = Vec3(2 * radius, 2 * radius, 0.1);
  init.flags = kSolid | kMovable | kRobot;
  init.led_count = 3;
  init.components.Add<DriveState>().wheel_base = 0.1;
  return init;
}

Space::EntityInit Wall(const std::string& id, uint16_t type, double x, double y, double sx,
                       double sy) {
  Space::EntityInit init;
  init.id = id;
  init.type = type;
  init.pose.position = Vec3(x, y, 0);
  init.geometry.shape = ShapeKind::kBox;
  init.geometry.size = Vec3(sx, sy, 0.5);
  init.flags = kSolid;
  return init;
}

std::vector<uint32_t> Gathered(const Space& space, double x0, double y0, double x1, double y1) {
  std::vector<uint32_t> out;
  space.Gather(x0, y0, x1, y1, out);
  return out;
}

bool HasSlot(const std::vector<uint32_t>& slots, uint32_t slot) {
  return std::find(slots.begin(), slots.end(), slot) != slots.end();
}

class core_test_space : public ::testing::Test {
 protected:
  core_test_space() {
    space.SetArena(Vec3(0, 0, 0.5), Vec3(10, 10, 1));
    robot_type = space.TypeId("marxbot");
    box_type = space.TypeId("box");
  }
  Space space;
  uint16_t robot_type = 0, box_type = 0;
};

TEST_F(core_test_space, TypeIdsAreStablePerLabel) {
  EXPECT_NE(robot_type, box_type);
  EXPECT_EQ(space.TypeId("marxbot"), robot_type);
  EXPECT_EQ(space.TypeLabel(box_type), "box");
  EXPECT_EQ(space.type_count(), 2u);
}

TEST_F(core_test_space, AddStoresTheEntityAndFindsItById) {
  const EntityHandle a = space.Add(Robot("a", robot_type, 1, 2));
  const EntityHandle b = space.Add(Wall("b", box_type, -1, -1, 1, 1));
  ASSERT_TRUE(a.valid());
  EXPECT_TRUE(space.IsAlive(a));
  EXPECT_TRUE(space.IsAlive(b));
  EXPECT_NE(a.index, b.index);
  EXPECT_EQ(space.alive_count(), 2u);
  EXPECT_EQ(space.id(a.index), "a");
  EXPECT_EQ(space.type(a.index), robot_type);
  EXPECT_EQ(space.pose(a.index).position, Vec3(1, 2, 0));
  EXPECT_TRUE(space.movable(a.index));
  EXPECT_FALSE(space.movable(b.index));
  EXPECT_EQ(space.leds(a.index).size(), 3u);
  EXPECT_EQ(space.leds(b.index).size(), 0u);
  ASSERT_NE(space.drive(a.index), nullptr);
  EXPECT_EQ(space.drive(a.index)->wheel_base, 0.1);
  EXPECT_EQ(space.drive(b.index), nullptr);
  EXPECT_EQ(space.light(a.index), nullptr);
  EXPECT_EQ(space.Find("a"), a);
  EXPECT_EQ(space.Find("b"), b);
  EXPECT_FALSE(space.Find("c").valid());
}

TEST_F(core_test_space, LightsShineInTheirColour) {
  Space::EntityInit init;
  init.id = "lamp";
  init.type = space.TypeId("light");
  init.flags = 0;
  init.color = Color{255, 255, 0, 255};
  init.led_count = 1;
  init.light_intensity = 2;
  const EntityHandle lamp = space.Add(init);
  ASSERT_NE(space.light(lamp.index), nullptr);
  EXPECT_EQ(space.light(lamp.index)->intensity, 2);
  EXPECT_EQ(space.leds(lamp.index)[0], init.color);
  // Robots' LEDs start off.
  const EntityHandle r = space.Add(Robot("r", robot_type, 0, 0));
  for (const Color& c : space.leds(r.index)) EXPECT_EQ(c, Color::Black());
}

TEST_F(core_test_space, RemoveForgetsTheEntity) {
  const EntityHandle a = space.Add(Robot("a", robot_type, 1, 2));
  const EntityHandle b = space.Add(Robot("b", robot_type, 3, 2));
  space.Remove(a);
  EXPECT_FALSE(space.IsAlive(a));
  EXPECT_FALSE(space.alive(a.index));
  EXPECT_TRUE(space.IsAlive(b));
  EXPECT_EQ(space.alive_count(), 1u);
  EXPECT_FALSE(space.Find("a").valid());
  EXPECT_EQ(space.Find("b"), b);
  // Removing twice is harmless.
  space.Remove(a);
  EXPECT_EQ(space.alive_count(), 1u);
}

// A component type of this test only: the space stores it like any other.
struct TestArm {
  static constexpr const char* kComponentName = "core_test_arm";
  double angle = 0;
  void Hash(StateHasher& h) const { h.Add(&angle, sizeof angle); }
};

TEST_F(core_test_space, EntitiesCarryOnlyTheComponentsTheyWereMadeWith) {
  Space::EntityInit with_arm = Robot("armed", robot_type, 1, 1);
  with_arm.components.Add<TestArm>().angle = 0.5;
  const Space::EntityInit copy = with_arm;  // templates are copied, components and all
  with_arm.components.Find<TestArm>()->angle = 0.7;
  const EntityHandle a = space.Add(with_arm);
  const EntityHandle b = space.Add(Robot("plain", robot_type, 2, 2));
  const EntityHandle w = space.Add(Wall("w", box_type, 0, 0, 1, 0.1));
  ASSERT_NE(space.Get<TestArm>(a.index), nullptr);
  EXPECT_EQ(space.Get<TestArm>(a.index)->angle, 0.7);
  EXPECT_EQ(copy.components.Find<TestArm>()->angle, 0.5);
  ASSERT_NE(space.drive(a.index), nullptr);
  EXPECT_EQ(space.drive(a.index)->wheel_base, 0.1);
  EXPECT_EQ(space.Get<TestArm>(b.index), nullptr);
  EXPECT_NE(space.drive(b.index), nullptr);
  EXPECT_EQ(space.drive(w.index), nullptr);
  EXPECT_TRUE(space.ComponentsOf(w.index).empty());
  EXPECT_EQ(space.ComponentsOf(a.index), (std::vector<ComponentType>{ComponentTypeOf<DriveState>(),
                                                                     ComponentTypeOf<TestArm>()}));
  EXPECT_EQ(ComponentName(ComponentTypeOf<TestArm>()), "core_test_arm");
  // The state hash sees the component's state.
  auto hash = [&] {
    StateHasher h;
    space.Hash(h);
    return h.value();
  };
  const uint64_t before = hash();
  space.Get<TestArm>(a.index)->angle = 0.9;
  EXPECT_NE(hash(), before);
  // A removed entity's components are gone; a new entity in its slot has its own.
  space.Remove(a);
  const EntityHandle c = space.Add(Robot("c", robot_type, 3, 3));
  EXPECT_EQ(c.index, a.index);
  EXPECT_EQ(space.Get<TestArm>(c.index), nullptr);
  EXPECT_EQ(space.Pool<TestArm>().owner(0), ComponentPoolBase::kNoOwner);
}

TEST_F(core_test_space, HandlesDetectReuseOfASlot) {
  const EntityHandle old = space.Add(Robot("a", robot_type, 1, 2));
  space.Remove(old);
  const EntityHandle fresh = space.Add(Robot("c", robot_type, -1, -2));
  EXPECT_EQ(fresh.index, old.index) << "the freed slot is reused";
  EXPECT_NE(fresh.generation, old.generation);
  EXPECT_FALSE(space.IsAlive(old)) << "a stale handle must not reach the new occupant";
  EXPECT_TRUE(space.IsAlive(fresh));
  EXPECT_EQ(space.HandleOf(fresh.index), fresh);
  // Removing through the stale handle leaves the new entity alone.
  space.Remove(old);
  EXPECT_TRUE(space.IsAlive(fresh));
  EXPECT_EQ(space.Find("c"), fresh);
  EXPECT_EQ(space.id(fresh.index), "c");
  EXPECT_EQ(space.pose(fresh.index).position, Vec3(-1, -2, 0));
  // An invalid or out-of-range handle is never alive.
  EXPECT_FALSE(space.IsAlive(EntityHandle{}));
  EXPECT_FALSE(space.IsAlive(EntityHandle{1000, 0}));
}

TEST_F(core_test_space, OfTypeListsAliveEntitiesInOrderAdded) {
  const EntityHandle r1 = space.Add(Robot("r1", robot_type, 1, 1));
  const EntityHandle w = space.Add(Wall("w", box_type, 0, 0, 1, 1));
  const EntityHandle r2 = space.Add(Robot("r2", robot_type, 2, 2));
  const EntityHandle r3 = space.Add(Robot("r3", robot_type, 3, 3));
  EXPECT_EQ(space.OfType(robot_type), (std::vector<uint32_t>{r1.index, r2.index, r3.index}));
  EXPECT_EQ(space.OfType(box_type), (std::vector<uint32_t>{w.index}));
  space.Remove(r2);
  EXPECT_EQ(space.OfType(robot_type), (std::vector<uint32_t>{r1.index, r3.index}));
  EXPECT_TRUE(space.OfType(space.TypeId("never_used")).empty());
  EXPECT_TRUE(space.OfType(999).empty());
}

TEST_F(core_test_space, GatherReturnsNeighboursNotFarEntities) {
  const EntityHandle centre = space.Add(Robot("centre", robot_type, 0, 0));
  const EntityHandle near = space.Add(Robot("near", robot_type, 0.3, 0.2));
  const EntityHandle far = space.Add(Robot("far", robot_type, 4, 4));
  const EntityHandle other_side = space.Add(Robot("other_side", robot_type, -4, 3));
  space.UpdateIndex();
  EXPECT_FALSE(space.index_dirty());
  const auto around = Gathered(space, -0.5, -0.5, 0.5, 0.5);
  EXPECT_TRUE(HasSlot(around, centre.index));
  EXPECT_TRUE(HasSlot(around, near.index));
  EXPECT_FALSE(HasSlot(around, far.index));
  EXPECT_FALSE(HasSlot(around, other_side.index));
  const auto corner = Gathered(space, 3.5, 3.5, 4.5, 4.5);
  EXPECT_TRUE(HasSlot(corner, far.index));
  EXPECT_FALSE(HasSlot(corner, centre.index));
}

TEST_F(core_test_space, GatherReturnsEachEntityOnce) {
  for (int i = 0; i < 50; ++i)
    space.Add(Robot("r" + std::to_string(i), robot_type, -4.5 + 0.18 * i, 0.1 * (i % 7)));
  space.Add(Wall("long", box_type, 0, -2, 9, 0.2));
  space.UpdateIndex();
  auto all = Gathered(space, -5, -5, 5, 5);
  EXPECT_EQ(all.size(), 51u);
  std::sort(all.begin(), all.end());
  EXPECT_EQ(std::adjacent_find(all.begin(), all.end()), all.end()) << "an entity came back twice";
}

TEST_F(core_test_space, GatherFindsABodyReachingIntoTheQueryFromANeighbouringCell) {
  // A large movable body whose centre lies outside the query rectangle but
  // whose footprint overlaps it.
  const EntityHandle big = space.Add(Robot("big", robot_type, 1.25, 0, 0.35));
  space.UpdateIndex();
  EXPECT_TRUE(HasSlot(Gathered(space, 0.85, -0.05, 0.95, 0.05), big.index));
}

TEST_F(core_test_space, WallsSpanningManyCellsAreFoundAlongTheirLengthOnce) {
  // One wall along the whole north edge and one along the west edge.
  const EntityHandle north = space.Add(Wall("north", box_type, 0, 4.95, 10, 0.1));
  const EntityHandle west = space.Add(Wall("west", box_type, -4.95, 0, 0.1, 9.8));
  space.UpdateIndex();
  for (double x : {-4.8, -2.0, 0.0, 3.3, 4.8}) {
    const auto hits = Gathered(space, x - 0.1, 4.7, x + 0.1, 4.9);
    EXPECT_EQ(std::count(hits.begin(), hits.end(), north.index), 1) << "x = " << x;
  }
  for (double y : {-4.7, 0.0, 4.0}) {
    const auto hits = Gathered(space, -4.9, y - 0.1, -4.7, y + 0.1);
    EXPECT_EQ(std::count(hits.begin(), hits.end(), west.index), 1) << "y = " << y;
  }
  // A query covering the whole arena sees each wall once, though both sit in many cells.
  const auto everything = Gathered(space, -5, -5, 5, 5);
  EXPECT_EQ(std::count(everything.begin(), everything.end(), north.index), 1);
  EXPECT_EQ(std::count(everything.begin(), everything.end(), west.index), 1);
  // Far from both: neither.
  const auto middle = Gathered(space, -0.5, -0.5, 0.5, 0.5);
  EXPECT_FALSE(HasSlot(middle, north.index));
  EXPECT_FALSE(HasSlot(middle, west.index));
}

TEST_F(core_test_space, GatherFindsEveryBoxAQueryTouchesAmongRobotsOnce) {
  // Small boxes and robots (one large, so that movable queries are widened
  // well beyond the boxes' cells) at random; queries of robot size anywhere.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> at(-4.8, 4.8), size(0.05, 0.6);
  space.Add(Robot("big", robot_type, 0, 0, 0.4));
  for (int i = 0; i < 200; ++i)
    space.Add(Robot("r" + std::to_string(i), robot_type, at(rng), at(rng)));
  struct Box {
    uint32_t slot;
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  for (int i = 0; i < 40; ++i) {
    const double x = at(rng), y = at(rng), sx = size(rng), sy = size(rng);
    const EntityHandle b = space.Add(Wall("b" + std::to_string(i), box_type, x, y, sx, sy));
    boxes.push_back({b.index, x - sx / 2, y - sy / 2, x + sx / 2, y + sy / 2});
  }
  space.UpdateIndex();
  for (int q = 0; q < 2000; ++q) {
    const double x = at(rng), y = at(rng), half = 0.05 + 0.25 * (q % 5);
    const auto hits = Gathered(space, x - half, y - half, x + half, y + half);
    for (const Box& b : boxes) {
      const bool overlaps =
          b.x0 <= x + half && x - half <= b.x1 && b.y0 <= y + half && y - half <= b.y1;
      const double cell = space.cell_size();
      const bool far = b.x0 > x + half + cell || x - half - cell > b.x1 || b.y0 > y + half + cell ||
                       y - half - cell > b.y1;
      const auto count = std::count(hits.begin(), hits.end(), b.slot);
      if (overlaps) {
        EXPECT_EQ(count, 1) << "query " << q << " misses a box it touches";
      }
      if (far) {
        EXPECT_EQ(count, 0) << "query " << q << " finds a box over a cell away";
      }
      EXPECT_LE(count, 1);
    }
  }
}

TEST_F(core_test_space, GatherSkipsNonSolidAndRemovedEntities) {
  Space::EntityInit ghost = Robot("ghost", robot_type, 0, 0);
  ghost.flags = kMovable;  // not solid
  const EntityHandle g = space.Add(ghost);
  const EntityHandle gone = space.Add(Robot("gone", robot_type, 0.2, 0));
  const EntityHandle wall = space.Add(Wall("w", box_type, 0, 0.5, 1, 0.1));
  space.UpdateIndex();
  EXPECT_TRUE(HasSlot(Gathered(space, -1, -1, 1, 1), gone.index));
  space.Remove(gone);
  space.Remove(wall);
  EXPECT_TRUE(space.index_dirty());
  space.UpdateIndex();
  const auto hits = Gathered(space, -1, -1, 1, 1);
  EXPECT_FALSE(HasSlot(hits, g.index));
  EXPECT_FALSE(HasSlot(hits, gone.index));
  EXPECT_FALSE(HasSlot(hits, wall.index));
}

TEST_F(core_test_space, GatherFollowsMovesAfterUpdateIndex) {
  const EntityHandle r = space.Add(Robot("r", robot_type, -3, -3));
  space.UpdateIndex();
  EXPECT_FALSE(HasSlot(Gathered(space, 2.5, 2.5, 3.5, 3.5), r.index));
  space.pose(r.index).position = Vec3(3, 3, 0);
  space.UpdateIndex();
  EXPECT_TRUE(HasSlot(Gathered(space, 2.5, 2.5, 3.5, 3.5), r.index));
  EXPECT_FALSE(HasSlot(Gathered(space, -3.5, -3.5, -2.5, -2.5), r.index));
}

TEST_F(core_test_space, HashChangesWithStateOnly) {
  const EntityHandle r = space.Add(Robot("r", robot_type, 1, 1));
  auto hash = [&] {
    StateHasher h;
    space.Hash(h);
    return h.value();
  };
  const uint64_t before = hash();
  EXPECT_EQ(hash(), before);
  space.pose(r.index).position.x() += 1e-9;
  EXPECT_NE(hash(), before);
}

// Over a 100 km arena the grid widens its cells instead of allocating
// 4e10 of them, and still finds what is near a query.
TEST_F(core_test_space, HugeArenaGridIsBoundedAndStillFindsNeighbours) {
  space.SetArena(Vec3(0, 0, 0.5), Vec3(1e5, 1e5, 1));
  const EntityHandle r = space.Add(Robot("r", robot_type, 30000, -20000));
  const EntityHandle w = space.Add(Wall("w", box_type, 0, 49999.95, 1e5, 0.1));
  space.UpdateIndex();
  const double cells = std::ceil(1e5 / space.cell_size()) * std::ceil(1e5 / space.cell_size());
  EXPECT_LE(cells, 1 << 20);
  EXPECT_GT(space.cell_size(), 0.5);
  EXPECT_TRUE(HasSlot(Gathered(space, 29999, -20001, 30001, -19999), r.index));
  EXPECT_TRUE(HasSlot(Gathered(space, -10, 49990, 10, 50000), w.index));
  // Queries far outside the arena, or at NaN, land in edge cells.
  EXPECT_TRUE(HasSlot(Gathered(space, -1e300, 4e4, 1e300, 1e300), w.index));
  const double nan = std::nan("");
  EXPECT_LE(Gathered(space, nan, nan, nan, nan).size(), 2u);
}

TEST_F(core_test_space, IndexBuiltOnThreadsIsTheOneThreadsIndex) {
  // Robots scattered over every band of rows (and some outside the arena,
  // filed in edge cells), a wall, and a removed robot.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> at(-6.0, 6.0);
  for (int i = 0; i < 3000; ++i) {
    space.Add(Robot("r" + std::to_string(i), robot_type, at(rng), at(rng), 0.05));
  }
  space.Add(Wall("w", box_type, 0, 4.9, 10, 0.2));
  space.Remove(space.Find("r17"));
  space.UpdateIndex();
  const std::vector<uint32_t> alone = space.movable_by_cell();
  ASSERT_EQ(alone.size(), 2999u);
  for (int threads : {2, 3, 8}) {
    ThreadPool pool(threads);
    space.set_pool(&pool);
    space.UpdateIndex();
    EXPECT_EQ(space.movable_by_cell(), alone) << threads << " threads";
    EXPECT_TRUE(HasSlot(Gathered(space, 4.5, 4.5, 5, 5), space.Find("w").index));
  }
  space.set_pool(nullptr);
}

TEST(core_test_cells, CellIndexIsTheCellOrTheNearestEdgeCell) {
  const int n = 10;
  EXPECT_EQ(ClampedCellIndex(0.0, n), 0);
  EXPECT_EQ(ClampedCellIndex(0.999, n), 0);
  EXPECT_EQ(ClampedCellIndex(1.0, n), 1);
  EXPECT_EQ(ClampedCellIndex(4.5, n), 4);
  EXPECT_EQ(ClampedCellIndex(9.999, n), 9);
  // Outside the grid, infinite or NaN: an edge cell, never an overflow.
  EXPECT_EQ(ClampedCellIndex(10.0, n), 9);
  EXPECT_EQ(ClampedCellIndex(-0.5, n), 0);
  EXPECT_EQ(ClampedCellIndex(-1e300, n), 0);
  EXPECT_EQ(ClampedCellIndex(1e300, n), 9);
  EXPECT_EQ(ClampedCellIndex(std::numeric_limits<double>::infinity(), n), 9);
  EXPECT_EQ(ClampedCellIndex(-std::numeric_limits<double>::infinity(), n), 0);
  EXPECT_EQ(ClampedCellIndex(std::nan(""), n), 0);
  EXPECT_EQ(ClampedCellIndex(3.0, 1), 0);
}

TEST_F(core_test_space, SmallArenaKeepsHalfMetreCells) {
  space.Add(Robot("r", robot_type, 0, 0));
  space.UpdateIndex();
  EXPECT_EQ(space.cell_size(), 0.5);
}

// Device instances and readings of a big swarm: past the first blocks
// (core/device.h) they come from huge-page blocks, and controllers keep
// pointers to them, so every address must stay put as robots are added.
struct TestInstance : InstanceBaseWithoutStream {
  using Interface = TestInstance;
  int value = -1;
};

TEST(core_test_device_blocks, InstancesKeepTheirAddressesAcrossBlocks) {
  InstanceStore<TestInstance> store;
  std::vector<TestInstance*> added;
  const RandomStream rng = RandomStream::For(1, "test", "");
  for (uint32_t i = 0; i < 70'000; ++i) {
    TestInstance& item = store.Add(EntityHandle{i, 0}, rng);
    EXPECT_EQ(item.value, -1);
    item.value = static_cast<int>(i);
    added.push_back(&item);
  }
  ASSERT_EQ(store.size(), 70'000u);
  for (uint32_t i = 0; i < 70'000; ++i) {
    ASSERT_EQ(&store[i], added[i]);
    ASSERT_EQ(store[i].value, static_cast<int>(i));
    ASSERT_EQ(store[i].robot.index, i);
  }
  store.Remove(added[40'000]);
  EXPECT_FALSE(store[40'000].alive);
  EXPECT_TRUE(store[39'999].alive && store[40'001].alive);
}

TEST(core_test_device_blocks, ArrayBlocksGiveZeroedSeparateArrays) {
  ArrayBlocks<uint32_t> blocks;
  std::vector<std::span<uint32_t>> taken;
  // 24 at a time, as a proximity ring: 1.2 million values, past the small blocks.
  for (uint32_t i = 0; i < 50'000; ++i) {
    const std::span<uint32_t> s = blocks.Take(24);
    ASSERT_EQ(s.size(), 24u);
    EXPECT_TRUE(std::all_of(s.begin(), s.end(), [](uint32_t v) { return v == 0; }));
    std::fill(s.begin(), s.end(), i);
    taken.push_back(s);
  }
  for (uint32_t i = 0; i < 50'000; ++i) {
    ASSERT_TRUE(std::all_of(taken[i].begin(), taken[i].end(), [i](uint32_t v) { return v == i; }));
  }
}

// Pages of [begin, end) resident now, without touching them.
size_t ResidentPages(uintptr_t begin, uintptr_t end) {
  const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  std::vector<unsigned char> in((end - begin + page - 1) / page);
  if (mincore(reinterpret_cast<void*>(begin), end - begin, in.data()) != 0) return 0;
  return static_cast<size_t>(
      std::count_if(in.begin(), in.end(), [](unsigned char c) { return c & 1; }));
}

bool KernelPopulates() {
  const size_t bytes = 1 << 16;
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  const bool ok = p != MAP_FAILED && madvise(p, bytes, MADV_POPULATE_WRITE) == 0;
  if (p != MAP_FAILED) munmap(p, bytes);
  return ok;
}

// A big swarm's arrays are mapped in by a background thread before the
// loader fills them (core/huge_pages.h): the whole 2 MB pages of the range
// are there without the caller touching them. (Fresh memory from mmap, so
// that no allocator has filled any of it.)
TEST(core_test_huge_pages, PrefaultMapsTheWholePagesBeforeTheyAreTouched) {
  if (!KernelPopulates()) GTEST_SKIP() << "this kernel has no MADV_POPULATE_WRITE (Linux < 5.14)";
  const size_t bytes = size_t{64} << 20;
  void* memory = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(memory, MAP_FAILED);
  constexpr uintptr_t kHuge = uintptr_t{2} << 20;
  const uintptr_t at = reinterpret_cast<uintptr_t>(memory);
  const uintptr_t begin = (at + kHuge - 1) & ~(kHuge - 1), end = (at + bytes) & ~(kHuge - 1);
  const size_t pages = (end - begin) / static_cast<size_t>(sysconf(_SC_PAGESIZE));
  EXPECT_EQ(ResidentPages(begin, end), 0u);
  AdviseHugePages(memory, bytes, Prefault::kInBackground);
  WaitForBackgroundPrefaults();
  EXPECT_EQ(ResidentPages(begin, end), pages);
  EXPECT_EQ(ResidentPages(at, begin), 0u);  // the part before the first whole page: left alone
  munmap(memory, bytes);
}

// ... and populating never changes what the memory holds, even while the
// caller is writing it.
TEST(core_test_huge_pages, PrefaultKeepsWhatTheArrayHolds) {
  std::vector<uint64_t> v;
  v.reserve(size_t{8} << 20);
  AdviseHugePages(v, Prefault::kInBackground);
  for (size_t i = 0; i < v.capacity(); ++i) v.push_back(i * 2654435761u);
  AdviseHugePages(v, Prefault::kInBackground);  // again, over memory already written
  WaitForBackgroundPrefaults();
  for (size_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], i * 2654435761u) << "at " << i;
}

}  // namespace
}  // namespace colony

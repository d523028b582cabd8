// Loading through a spec: the experiment file is read into plain values
// (ExperimentSpec), which a program may inspect and change before
// Simulation::Create builds them.
#include <variant>

#include "tests/test_util.h"

namespace colony::testing {
namespace {

// Walls, one robot, a <distribute> block of boxes, two engines (lines 2-8).
const char kFile[] =
    "<colony><framework><system threads=\"2\"/><experiment length=\"5\" ticks_per_second=\"20\" "
    "random_seed=\"9\"/>"
    "</framework><controllers/>\n"
    "<arena size=\"6,4,1\" center=\"0,0,0.5\">\n"
    "<walls thickness=\"0.1\" height=\"0.3\" color=\"red\"/>\n"
    "<cylinder id=\"post\" radius=\"0.1\" height=\"0.5\"><body position=\"1,1,0\"/></cylinder>\n"
    "<distribute><position method=\"uniform\" min=\"-2,-1,0\" max=\"2,1,0\"/>"
    "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>\n"
    "<entity quantity=\"5\" base_num=\"10\"><box id=\"crate\" size=\"0.1,0.1,0.1\" "
    "movable=\"true\"/></entity></distribute>\n"
    "</arena>\n"
    "<physics_engines><dynamics2d id=\"d2d\"/></physics_engines><output "
    "hash_every=\"3\"/></colony>";

ExperimentSpec ReadText(const std::string& text) {
  ExperimentOptions options;
  options.text = text;
  return ReadExperimentSpec(options);
}

TEST(ExperimentSpec, HoldsTheFileAsValues) {
  if (!HaveEngine("dynamics2d")) GTEST_SKIP() << "the file uses dynamics2d";
  const ExperimentSpec spec = ReadText(kFile);
  EXPECT_EQ(spec.file, "<string>");
  EXPECT_EQ(spec.threads, 2);
  EXPECT_EQ(spec.seed, 9u);
  EXPECT_EQ(spec.length_ticks, 100u);
  EXPECT_DOUBLE_EQ(spec.dt, 0.05);
  EXPECT_EQ(spec.output.hash_every, 3u);
  ASSERT_EQ(spec.engines.size(), 1u);
  EXPECT_EQ(spec.engines[0].plugin.label, "dynamics2d");
  EXPECT_EQ(spec.engines[0].plugin.id, "d2d");
  EXPECT_FALSE(spec.engines[0].region.has_value());
  EXPECT_EQ(spec.arena.size, Vec3(6, 4, 1));
  // The walls are four fixed boxes, described, with the line of <walls>.
  ASSERT_EQ(spec.arena.walls.size(), 4u);
  for (const EntityDesc& wall : spec.arena.walls) {
    EXPECT_EQ(wall.type, "box");
    EXPECT_EQ(wall.line, 3);
    EXPECT_EQ(wall.init.flags, kSolid);
    EXPECT_EQ(wall.init.geometry.height(), 0.3);
    EXPECT_EQ(wall.init.color, *ParseColor("red"));
  }
  EXPECT_EQ(spec.arena.walls[0].init.id, "wall_north");
  EXPECT_EQ(spec.arena.walls[0].init.pose.position, Vec3(0, 2 - 0.05, 0));
  EXPECT_EQ(spec.arena.walls[0].init.geometry.size, Vec3(6, 0.1, 0.3));
  // Then the entities and blocks, in file order.
  ASSERT_EQ(spec.arena.contents.size(), 2u);
  const auto& post = std::get<EntityDesc>(spec.arena.contents[0]);
  EXPECT_EQ(post.type, "cylinder");
  EXPECT_EQ(post.init.id, "post");
  EXPECT_EQ(post.line, 4);
  EXPECT_EQ(post.init.pose.position, Vec3(1, 1, 0));
  const auto& block = std::get<DistributeSpec>(spec.arena.contents[1]);
  EXPECT_EQ(block.quantity, 5);
  EXPECT_EQ(block.base_num, 10);
  EXPECT_EQ(block.line, 5);
  EXPECT_EQ(block.entity_line, 6);
  EXPECT_EQ(block.entity.type, "box");
  EXPECT_EQ(block.entity.init.id, "crate");
  EXPECT_EQ(block.entity.init.flags, kSolid | kMovable);
  EXPECT_EQ(block.position.method, DistributeDraw::Method::kUniform);
  EXPECT_TRUE(block.orientation.degrees);
}

TEST(ExperimentSpec, CreatesWhatItHolds) {
  if (!HaveEngine("dynamics2d")) GTEST_SKIP() << "the file uses dynamics2d";
  const ExperimentSpec spec = ReadText(kFile);
  auto sim = Simulation::Create(spec);
  EXPECT_EQ(sim->threads(), 2);
  EXPECT_EQ(sim->length_ticks(), 100u);
  for (const char* id :
       {"wall_north", "wall_south", "wall_east", "wall_west", "post", "crate10", "crate14"}) {
    EXPECT_TRUE(sim->space().Find(id).valid()) << id;
  }
  EXPECT_FALSE(sim->space().Find("crate15").valid());
  EXPECT_EQ(sim->space().alive_count(), 4u + 1u + 5u);
}

TEST(ExperimentSpec, OneSpecCreatesTheSameSimulationAsLoading) {
  if (!HaveEngine("dynamics2d")) GTEST_SKIP() << "the file uses dynamics2d";
  const ExperimentSpec spec = ReadText(kFile);
  auto a = Simulation::Create(spec);
  auto b = Simulation::Create(spec);  // a spec can be created from again
  auto c = LoadXml(kFile);
  for (int t = 0; t < 10; ++t) {
    a->Step();
    b->Step();
    c->Step();
  }
  EXPECT_EQ(a->StateHash(), b->StateHash());
  EXPECT_EQ(a->StateHash(), c->StateHash());
  EXPECT_EQ(a->ResolvedXml(), c->ResolvedXml());
}

TEST(ExperimentSpec, ProgramsMayChangeItBeforeCreating) {
  if (!HaveEngine("dynamics2d")) GTEST_SKIP() << "the file uses dynamics2d";
  ExperimentSpec spec = ReadText(kFile);
  auto& block = std::get<DistributeSpec>(spec.arena.contents[1]);
  block.quantity = 12;
  block.entity.init.color = Color{0, 0, 255, 255};
  EntityDesc extra = std::get<EntityDesc>(spec.arena.contents[0]);
  extra.init.id = "post2";
  extra.init.pose.position = Vec3(-1, 1, 0);
  spec.arena.contents.push_back(extra);
  spec.arena.walls.clear();
  auto sim = Simulation::Create(spec);
  EXPECT_EQ(sim->space().alive_count(), 1u + 12u + 1u);
  EXPECT_EQ(sim->space().color(sim->space().Find("crate21").index), (Color{0, 0, 255, 255}));
  EXPECT_FALSE(sim->space().Find("wall_north").valid());
  EXPECT_TRUE(sim->space().Find("post2").valid());
}

TEST(ExperimentSpec, ProblemsFoundBuildingNameTheSpecLines) {
  if (!HaveEngine("dynamics2d")) GTEST_SKIP() << "the file uses dynamics2d";
  ExperimentSpec spec = ReadText(kFile);
  EntityDesc clash = std::get<EntityDesc>(spec.arena.contents[0]);
  clash.line = 42;  // where a program says it came from
  spec.arena.contents.push_back(clash);
  try {
    Simulation::Create(spec);
    ADD_FAILURE() << "a duplicate id was accepted";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(Mentions(e.what(), {"<string>:42:", "<cylinder id=\"post\">",
                                    "duplicate entity id 'post'", "first defined at line 4"}));
  }
}

}  // namespace
}  // namespace colony::testing

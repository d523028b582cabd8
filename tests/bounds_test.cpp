// Bounded input: every size and count an experiment file gives is either
// refused with a message naming the attribute and the bound, or runs within
// memory that does not grow with empty space (core/bounds.h). Suites are
// named bounds* so `ctest -R bounds` selects them.
#include "core/bounds.h"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/test_util.h"

namespace colony::testing {
namespace {

// The highest resident memory of this process so far (bytes).
double PeakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss * 1024.0;  // kilobytes on Linux
}

// Diffusing marXbots that sense, signal and see each other (proximity,
// range-and-bearing with occlusion checks, omnidirectional camera on the LED
// medium), in a walled square arena `side` metres wide, placed near its
// centre (line 2 is the <arena>).
std::string Swarm(const std::string& side, int robots) {
  return "<colony><framework><experiment length=\"1\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework>\n"
         "<arena size=\"" +
         side + "," + side +
         ",1\" center=\"0,0,0.5\">\n"
         "<walls thickness=\"0.1\" height=\"0.5\"/>\n"
         "<distribute><position method=\"uniform\" min=\"-5,-5,0\" max=\"5,5,0\"/>"
         "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
         "<entity quantity=\"" +
         std::to_string(robots) +
         "\"><marxbot id=\"mb\"><controller config=\"dc\"/></marxbot>"
         "</entity></distribute>\n"
         "<box id=\"b\" size=\"1,1,0.5\" movable=\"false\"><body position=\"7,7,0\"/></box>\n"
         "</arena>\n"
         "<controllers><diffusion id=\"dc\" library=\"diffusion\">"
         "<actuators><differential_steering/><leds color=\"red\"/><range_and_bearing/></actuators>"
         "<sensors><proximity/><range_and_bearing/><omnidirectional_camera/></sensors>"
         "<params velocity=\"0.3\"/></diffusion></controllers>\n"
         "<media><range_and_bearing id=\"rab\" check_occlusions=\"true\"/></media>\n"
         "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines></colony>";
}

// --- Arena size ----------------------------------------------------------------

// Arenas of 10 km and 100 km (the largest accepted) load and run in memory
// that depends on the robots, not on the empty area: before the bound, a
// 10 km arena took 4.7 GB and 12 s to load.
TEST(bounds, LargeArenasRunInBoundedMemory) {
  for (const std::string side : {"1e4", "1e5"}) {
    auto sim = LoadXml(Swarm(side, 100));
    for (int t = 0; t < 5; ++t) sim->Step();
    EXPECT_EQ(sim->robot_count(), 100u);
    const double extent = std::stod(side);
    const double cells =
        std::ceil(extent / sim->space().cell_size()) * std::ceil(extent / sim->space().cell_size());
    EXPECT_LE(cells, kMinGridCells) << side;
    EXPECT_LT(PeakResidentBytes(), 1e9) << "arena " << side << " m";
  }
}

// The arenas of the tests and examples keep their 0.5 m cells (so their
// results do not change); a larger one gets larger cells.
TEST(bounds, GridCellsGrowOnlyPastTheCap) {
  auto small = LoadXml(Swarm("200", 10));
  EXPECT_EQ(small->space().cell_size(), 0.5);
  auto large = LoadXml(Swarm("2000", 10));
  EXPECT_GT(large->space().cell_size(), 0.5);
}

TEST(bounds, HugeArenasAreRefusedNamingTheAttribute) {
  for (const std::string side : {"1e9", "1e12", "1e300"}) {
    EXPECT_TRUE(
        Mentions(LoadError(Swarm(side, 1)), {"<string>:2:", "<arena>", "attribute 'size'",
                                             "out of range", "accepted: a number in (0, 100000]"}))
        << side;
  }
  const std::string tall =
      "<colony><framework><experiment length=\"1\"/></framework>\n"
      "<arena size=\"10,10,1e6\"/></colony>";
  EXPECT_TRUE(
      Mentions(LoadError(tall), {"<string>:2:", "attribute 'size'", "'10,10,1e6'", "(0, 100000]"}));
}

TEST(bounds, ArenaCentreFarFromTheOriginIsRefused) {
  const std::string xml =
      "<colony><framework><experiment length=\"1\"/></framework>\n"
      "<arena size=\"10,10,1\" center=\"1e12,0,0.5\"/></colony>";
  EXPECT_TRUE(
      Mentions(LoadError(xml), {"<string>:2:", "<arena>", "attribute 'center'", "'1e12,0,0.5'",
                                "accepted: a number in [-100000, 100000]"}));
}

TEST(bounds, TooManyDitchesAreRefused) {
  std::string ditches;
  for (int i = 0; i < 300; ++i) ditches += "<ditch center=\"0,0\" size=\"0.1,0.1\"/>\n";
  const std::string xml =
      "<colony><framework><experiment length=\"1\"/></framework>\n"
      "<arena size=\"10,10,1\"><floor>\n" +
      ditches + "</floor></arena></colony>";
  // The 257th ditch, on line 2 + 257.
  EXPECT_TRUE(Mentions(LoadError(xml), {"<string>:259:", "<ditch>", "300 ditches", "at most 256"}));
}

// A floor image whose header claims 20000 x 20000 pixels (1.6 GB decoded).
TEST(bounds, HugeFloorImageIsRefused) {
  auto crc = [](const std::string& bytes) {
    uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
      c ^= b;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
  };
  auto be32 = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(static_cast<uint32_t>(data.size())) + type + data + be32(crc(type + data));
  };
  const std::string ihdr = be32(20000) + be32(20000) + std::string("\x08\x02\x00\x00\x00", 5);
  const auto dir = FreshTempDir("colony_bounds", "floor");
  std::filesystem::create_directories(dir);
  const auto png = dir / "huge.png";
  std::ofstream(png, std::ios::binary) << std::string("\x89PNG\r\n\x1a\n", 8) << chunk("IHDR", ihdr)
                                       << chunk("IDAT", "") << chunk("IEND", "");
  const std::string xml =
      "<colony><framework><experiment length=\"1\"/></framework>\n"
      "<arena size=\"10,10,1\"><floor source=\"image\" path=\"" +
      png.string() + "\"/></arena></colony>";
  EXPECT_TRUE(
      Mentions(LoadError(xml), {"<string>:2:", "<floor>", "attribute 'path'",
                                "is 20000 x 20000 pixels", "accepted: at most 268435456 pixels"}));
  std::filesystem::remove_all(dir);
}

// --- Counts and memory -----------------------------------------------------------

// The distance scanner's bin count comes from scans_per_second: a tiny one
// would overflow it.
TEST(bounds, ScannerBinCountIsBounded) {
  const std::string xml =
      "<colony><framework><experiment length=\"1\"/></framework>\n"
      "<controllers><diffusion id=\"dc\" "
      "library=\"diffusion\"><actuators><differential_steering/></actuators>"
      "\n<sensors><proximity/><distance_scanner "
      "scans_per_second=\"1e-300\"/></sensors></diffusion></controllers>\n"
      "<arena size=\"4,4,1\"/></colony>";
  EXPECT_TRUE(
      Mentions(LoadError(xml), {"<string>:3:", "<distance_scanner>", "attribute 'scans_per_second'",
                                "'1e-300' is out of range", "accepted: a number in [0.01, 2]"}));
}

TEST(bounds, DistributeQuantityHasAnUpperBound) {
  EXPECT_TRUE(Mentions(LoadError(Swarm("20", 1'000'000'000)),
                       {"<entity>", "attribute 'quantity'", "'1000000000' is out of range",
                        "accepted: a whole number in [1, 10000000]"}));
}

// Robots that would need more memory than the machine has are refused before
// any is made, with the figure.
TEST(bounds, RobotsBeyondTheMachinesMemoryAreRefused) {
  // A distance scanner with its finest bins holds 192 kB per robot:
  // 10,000,000 robots would need 2 TB.
  const std::string xml =
      "<colony><framework><experiment length=\"1\"/></framework>\n"
      "<controllers><diffusion id=\"dc\" "
      "library=\"diffusion\"><actuators><differential_steering/></actuators>"
      "<sensors><proximity/><distance_scanner "
      "scans_per_second=\"0.01\"/></sensors></diffusion></controllers>\n"
      "<arena size=\"1e5,1e5,1\">\n<distribute><position method=\"uniform\" min=\"-1,-1,0\" "
      "max=\"1,1,0\"/>"
      "<orientation method=\"constant\" values=\"0,0,0\"/>\n"
      "<entity quantity=\"10000000\"><marxbot id=\"mb\"><controller "
      "config=\"dc\"/></marxbot></entity>"
      "</distribute></arena>\n"
      "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines></colony>";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string message = LoadError(xml);
  EXPECT_TRUE(
      Mentions(message, {"<string>:5:", "<entity>", "attribute 'quantity'",
                         "10000000 marxbot entities", "would need about", "1961 GB of memory",
                         "196 kB each", "this machine has", "accepted: at most"}));
  // Refused before placing anything.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

// All <distribute> blocks are estimated together, before any robot is made.
TEST(bounds, MemoryEstimateCountsEveryDistributeBlock) {
  // 20 blocks of 10,000,000 robots at about 4 kB: 800 GB together.
  std::string blocks;
  for (int b = 0; b < 20; ++b) {
    blocks +=
        "<distribute><position method=\"uniform\" min=\"-1,-1,0\" max=\"1,1,0\"/>"
        "<orientation method=\"constant\" values=\"0,0,0\"/><entity quantity=\"10000000\">"
        "<marxbot id=\"mb" +
        std::to_string(b) + "_\"><controller config=\"dc\"/></marxbot></entity></distribute>\n";
  }
  const std::string xml =
      "<colony><framework><experiment length=\"1\"/></framework>\n"
      "<controllers><diffusion id=\"dc\" library=\"diffusion\"/></controllers>\n"
      "<arena size=\"100,100,1\">\n" +
      blocks +
      "</arena>\n"
      "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines></colony>";
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(
      Mentions(LoadError(xml), {"<entity>", "attribute 'quantity'", "10000000 marxbot entities",
                                "would need about", "(about 4.1 kB each", "this machine has"}));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

// --- XML ---------------------------------------------------------------------------

TEST(bounds, SecondRootElementIsRefusedWithItsLine) {
  const std::string xml =
      "<colony>\n<framework><experiment length=\"1\"/></framework>\n<arena size=\"2,2,1\"/>\n"
      "</colony>\n<!-- a comment may follow -->\n<colony>\n</colony>\n";
  EXPECT_TRUE(Mentions(
      LoadError(xml), {"<string>:6:", "a second root element <colony>", "after </colony>", "line 1",
                       "accepted: one root element, followed only by comments"}));
}

TEST(bounds, TextAfterTheRootElementIsRefused) {
  const std::string xml =
      "<colony>\n<framework><experiment length=\"1\"/></framework>\n<arena size=\"2,2,1\"/>\n"
      "</colony>\nstray text <arena size=\"1,1,1\"/>\n";
  const std::string message = LoadError(xml);
  EXPECT_TRUE(Mentions(message, {"<string>:5:", "after </colony>"}));
}

TEST(bounds, TextToTheEndAfterTheRootElementIsRefused) {
  const std::string xml =
      "<colony>\n<framework><experiment length=\"1\"/></framework>\n<arena size=\"2,2,1\"/>\n"
      "</colony>\nstray text\n";
  EXPECT_TRUE(Mentions(LoadError(xml), {"<string>:5:", "text outside the root element",
                                        "accepted: one root element"}));
}

TEST(bounds, CommentsAfterTheRootElementAreFine) {
  const std::string xml =
      "<colony>\n<framework><experiment length=\"1\"/></framework>\n<arena size=\"2,2,1\"/>\n"
      "</colony>\n<!-- the end -->\n\n";
  EXPECT_EQ(LoadError(xml), "");
}

// --- Threads ---------------------------------------------------------------------

// 0 threads means the calling thread only: the simulation reports 1.
TEST(bounds, ZeroThreadsResolveToOne) {
  const std::string xml =
      "<colony><framework><system threads=\"0\"/><experiment length=\"1\"/></framework>"
      "<arena size=\"2,2,1\"/></colony>";
  EXPECT_EQ(LoadXml(xml)->threads(), 1);
  EXPECT_EQ(LoadXml(xml, {}, 0)->threads(), 1);
  EXPECT_EQ(LoadXml(xml, {}, 3)->threads(), 3);
}

// The table of bounds in docs/experiment-files.md states the figures of
// core/bounds.h (it is written by hand: this keeps it true).
TEST(bounds, DocumentedTableMatchesTheCode) {
  const std::string doc = ReadFile(COLONY_SOURCE_DIR "/docs/experiment-files.md");
  auto row = [&](const std::string& first_cell) {
    const size_t k = doc.find("\n| " + first_cell + " |");
    return k == std::string::npos ? std::string()
                                  : doc.substr(k + 1, doc.find('\n', k + 1) - k - 1);
  };
  auto whole = [](double v) { return std::to_string(static_cast<int64_t>(v)); };
  EXPECT_NE(row("`arena` `size`, each axis").find("(0, " + whole(kMaxArenaExtent) + "] m"),
            std::string::npos);
  EXPECT_NE(row("`arena` `center`, each axis")
                .find("[-" + whole(kMaxArenaExtent) + ", " + whole(kMaxArenaExtent) + "]"),
            std::string::npos);
  EXPECT_NE(row("`<ditch>` elements in `<floor>`").find("at most " + std::to_string(kMaxDitches)),
            std::string::npos);
  EXPECT_EQ(kMaxFloorImagePixels, uint64_t{1} << 28);
  EXPECT_NE(row("floor image (`source=\"image\"`)").find("at most 2^28 pixels"), std::string::npos);
  EXPECT_NE(row("`distribute/entity` `quantity`")
                .find("[1, " + std::to_string(kMaxDistributeQuantity) + "]"),
            std::string::npos);
  EXPECT_NE(doc.find(std::to_string(kEstimatedBytesPerRobot / 1024) + " kB per robot and " +
                     std::to_string(kEstimatedBytesPerEntity / 1024) + " kB per other entity"),
            std::string::npos);
}

}  // namespace
}  // namespace colony::testing

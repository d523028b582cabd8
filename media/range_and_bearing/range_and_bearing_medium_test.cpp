// The range-and-bearing medium's index: this tick's messages, where their
// senders are, and a grid whose runs hold every sender a receiver may hear.
#include "media/range_and_bearing/range_and_bearing_medium.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "actuators/range_and_bearing/range_and_bearing.h"
#include "core/registry.h"
#include "media/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadXml;
using testing::ReadmeAttributes;

// Sends its id's last character as byte 0, or nothing with param silent="true".
class RabIdle : public Controller {
 public:
  void Init(const Params& params) override {
    auto& rab = GetActuator<RangeAndBearingActuator>("range_and_bearing");
    if (params.GetBool("silent", false)) {
      rab.Clear();
    } else {
      rab.SetByte(0, static_cast<uint8_t>(id().back()));
    }
  }
  void ControlStep() override {}
};

COLONY_REGISTER_CONTROLLER(RabIdle, "rab_idle", "test: sends one byte");

RangeAndBearingMedium* Index(Simulation& sim) {
  for (const auto& m : sim.media()) {
    if (m->label() == "range_and_bearing") return dynamic_cast<RangeAndBearingMedium*>(m.get());
  }
  return nullptr;
}

std::string Robot(const std::string& id, double x, double y, const std::string& config = "tx") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + std::to_string(x) + "," +
         std::to_string(y) + ",0\"/><controller config=\"" + config + "\"/></marxbot>";
}

const std::string kControllers =
    "<rab_idle id=\"tx\"><actuators><range_and_bearing range=\"1.2\"/></actuators></rab_idle>"
    "<rab_idle id=\"short\"><actuators><range_and_bearing range=\"0.8\" "
    "data_size=\"3\"/></actuators></rab_idle>"
    "<rab_idle id=\"quiet\"><actuators><range_and_bearing/></actuators><params "
    "silent=\"true\"/></rab_idle>";

TEST(RangeAndBearingMedium, IndexesThisTicksMessagesWhereTheirSendersAre) {
  auto sim = LoadXml(Experiment(
      Robot("a", 1, 0.5) + Robot("b", -1, 0, "short") + Robot("c", 0, -1, "quiet"), kControllers));
  sim->Step();
  ASSERT_EQ(sim->media().size(), 1u);  // none declared: one with default settings
  const RangeAndBearingMedium& m = *Index(*sim);
  EXPECT_EQ(m.id(), "range_and_bearing");
  EXPECT_TRUE(m.check_occlusions());
  ASSERT_EQ(m.message_count(), 2u);  // c is silent
  EXPECT_DOUBLE_EQ(m.max_range(), 1.2);
  EXPECT_DOUBLE_EQ(m.cell_size(), 1.2);  // the largest range
  for (size_t i = 0; i < m.message_count(); ++i) {
    const auto& msg = m.messages()[i];
    const auto data = m.payload(msg);
    EXPECT_FLOAT_EQ(msg.z, 0.147 / 2);  // mid-height of the marXbot
    if (msg.slot == sim->space().Find("a").index) {
      EXPECT_DOUBLE_EQ(msg.x, 1);
      EXPECT_DOUBLE_EQ(msg.y, 0.5);
      EXPECT_FLOAT_EQ(msg.range2, 1.2 * 1.2);
      ASSERT_EQ(data.size(), 10u);
      EXPECT_EQ(data[0], 'a');
    } else {
      EXPECT_EQ(msg.slot, sim->space().Find("b").index);
      EXPECT_DOUBLE_EQ(msg.x, -1);
      EXPECT_FLOAT_EQ(msg.range2, 0.8 * 0.8);
      ASSERT_EQ(data.size(), 3u);
      EXPECT_EQ(data[0], 'b');
    }
  }
  // A removed robot sends nothing from the next tick on.
  sim->RemoveEntity(sim->space().Find("a"));
  sim->Step();
  ASSERT_EQ(m.message_count(), 1u);
  EXPECT_EQ(m.messages()[0].slot, sim->space().Find("b").index);
}

TEST(RangeAndBearingMedium, DeclaredSettingsAreUsed) {
  auto sim = LoadXml(
      Experiment(Robot("a", 0, 0, "quiet"), kControllers, "4,4,1",
                 "<media><range_and_bearing id=\"ir\" check_occlusions=\"false\" range=\"2\" "
                 "cell_size=\"0.5\"/></media>"));
  sim->Step();
  const RangeAndBearingMedium& m = *Index(*sim);
  EXPECT_EQ(m.id(), "ir");
  EXPECT_FALSE(m.check_occlusions());
  EXPECT_DOUBLE_EQ(m.default_range(), 2);
  EXPECT_DOUBLE_EQ(m.cell_size(), 0.5);
}

TEST(RangeAndBearingMedium, TheGridStaysSmallForTinyRangesInLargeArenas) {
  // 1 cm range over 200 x 200 m would be 4e8 cells: the cells grow instead.
  auto sim = LoadXml(Experiment(
      Robot("a", 0, 0, "tiny"),
      "<rab_idle id=\"tiny\"><actuators><range_and_bearing range=\"0.01\"/></actuators></rab_idle>",
      "200,200,1"));
  sim->Step();
  const double cell = Index(*sim)->cell_size();
  EXPECT_LE(std::ceil(200 / cell) * std::ceil(200 / cell), 4096.0);
  EXPECT_EQ(Index(*sim)->message_count(), 1u);
}

TEST(RangeAndBearingMedium, CandidateRunsHoldEverySenderWithinReach) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> coordinate(-4.8, 4.8);
  const std::string arena =
      "<distribute><position method=\"uniform\" min=\"-4.8,-4.8,0\" max=\"4.8,4.8,0\"/>"
      "<orientation method=\"constant\" values=\"0,0,0\"/>"
      "<entity quantity=\"300\" max_trials=\"100\"><marxbot id=\"r\"><controller "
      "config=\"tx\"/></marxbot></entity>"
      "</distribute>";
  for (const std::string media :
       {"", "<media><range_and_bearing id=\"m\" cell_size=\"0.25\"/></media>",
        "<media><range_and_bearing id=\"m\" cell_size=\"20\"/></media>"}) {
    auto sim = LoadXml(Experiment(arena, kControllers, "10,10,1", media));
    sim->Step();
    const RangeAndBearingMedium& m = *Index(*sim);
    ASSERT_EQ(m.message_count(), 300u);
    for (int q = 0; q < 200; ++q) {
      const double x = coordinate(gen) * 1.1, y = coordinate(gen) * 1.1;
      std::vector<uint32_t> seen;
      m.ForEachCandidateRun(x, y, m.max_range(), [&](uint32_t b, uint32_t e) {
        for (uint32_t i = b; i < e; ++i) seen.push_back(i);
      });
      std::sort(seen.begin(), seen.end());
      EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end());
      for (uint32_t i = 0; i < m.message_count(); ++i) {
        const auto& msg = m.messages()[i];
        if (std::hypot(msg.x - x, msg.y - y) > m.max_range()) continue;
        EXPECT_TRUE(std::binary_search(seen.begin(), seen.end(), i)) << media << " query " << q;
      }
    }
  }
}

TEST(RangeAndBearingMedium, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<Medium>::Get().Find("range_and_bearing");
  ASSERT_NE(entry, nullptr);
  auto names = entry->info.AttributeNames();
  names.insert(names.begin(), "id");
  EXPECT_EQ(ReadmeAttributes("media/range_and_bearing/README.md", "## XML"), names);
}

}  // namespace
}  // namespace colony

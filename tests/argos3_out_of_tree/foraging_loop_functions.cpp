#include "foraging_loop_functions.h"

#include <argos3/core/simulator/simulator.h>
#include <argos3/core/utility/configuration/argos_configuration.h>
#include <argos3/plugins/robots/foot-bot/simulator/footbot_entity.h>

#include "footbot_foraging.h"

static const Real NEST_X = -1.0;

CForagingLoopFunctions::CForagingLoopFunctions()
    : m_cFoodX(-0.6, 1.7),
      m_cFoodY(-1.7, 1.7),
      m_fPickUpRadius(0.15),
      m_pcRNG(NULL),
      m_unCollected(0),
      m_unArrivals(0) {}

CVector2 CForagingLoopFunctions::RandomFoodPosition() {
  return CVector2(m_pcRNG->Uniform(m_cFoodX), m_pcRNG->Uniform(m_cFoodY));
}

void CForagingLoopFunctions::Init(TConfigurationNode& t_tree) {
  /* As ARGoS's loop functions read theirs: <foraging items="20" radius="0.15"/> */
  TConfigurationNode& tForaging = GetNode(t_tree, "foraging");
  UInt32 unItems = 0;
  GetNodeAttribute(tForaging, "items", unItems);
  GetNodeAttributeOrDefault(tForaging, "radius", m_fPickUpRadius, m_fPickUpRadius);
  m_pcRNG = CRandom::CreateRNG("argos");
  for (UInt32 i = 0; i < unItems; ++i) m_cFoodPos.push_back(RandomFoodPosition());
  m_cOutput.open("foraging.txt", std::ios_base::trunc | std::ios_base::out);
  m_cOutput << "# clock\twalking\tresting\tcollected" << std::endl;
}

CColor CForagingLoopFunctions::GetFloorColor(const CVector2& c_position_on_plane) {
  if (c_position_on_plane.GetX() < NEST_X) return CColor::GRAY50;
  for (size_t i = 0; i < m_cFoodPos.size(); ++i) {
    if (SquareDistance(c_position_on_plane, m_cFoodPos[i]) < m_fPickUpRadius * m_fPickUpRadius) {
      return CColor::BLACK;
    }
  }
  return CColor::WHITE;
}

void CForagingLoopFunctions::PreStep() {
  UInt32 unWalking = 0, unResting = 0;
  CSpace::TMapPerType& tFootBots = GetSpace().GetEntitiesByType("foot-bot");
  for (CSpace::TMapPerType::iterator it = tFootBots.begin(); it != tFootBots.end(); ++it) {
    CFootBotEntity& cFootBot = *any_cast<CFootBotEntity*>(it->second);
    CFootBotForaging& cController =
        dynamic_cast<CFootBotForaging&>(cFootBot.GetControllableEntity().GetController());
    if (cController.IsResting()) {
      ++unResting;
      if (m_mapWasResting.count(it->first) && !m_mapWasResting[it->first]) ++m_unArrivals;
    } else {
      ++unWalking;
    }
    m_mapWasResting[it->first] = cController.IsResting();
    const CVector3& cPos3 = cFootBot.GetEmbodiedEntity().GetOriginAnchor().Position;
    const CVector2 cPos(cPos3.GetX(), cPos3.GetY());
    CFootBotForaging::SFoodData& sFood = cController.GetFoodData();
    if (sFood.HasFoodItem) {
      if (cPos.GetX() < NEST_X) {
        /* Delivered: the item appears again somewhere else */
        m_cFoodPos[sFood.FoodItemIdx] = RandomFoodPosition();
        sFood.HasFoodItem = false;
        ++sFood.TotalFoodItems;
        ++m_unCollected;
      }
    } else if (cController.IsExploring() && cPos.GetX() > NEST_X) {
      for (size_t i = 0; i < m_cFoodPos.size(); ++i) {
        if (SquareDistance(cPos, m_cFoodPos[i]) < m_fPickUpRadius * m_fPickUpRadius) {
          /* Taken: out of the arena until delivered */
          m_cFoodPos[i].Set(100.0, 100.0);
          sFood.HasFoodItem = true;
          sFood.FoodItemIdx = i;
          break;
        }
      }
    }
  }
  m_cOutput << GetSpace().GetSimulationClock() << "\t" << unWalking << "\t" << unResting << "\t"
            << m_unCollected << std::endl;
}

void CForagingLoopFunctions::PostExperiment() {
  /* What the controllers counted must match what was delivered */
  size_t unCounted = 0;
  CSpace::TMapPerType& tFootBots = GetSpace().GetEntitiesByType("foot-bot");
  for (CSpace::TMapPerType::iterator it = tFootBots.begin(); it != tFootBots.end(); ++it) {
    CFootBotEntity& cFootBot = *any_cast<CFootBotEntity*>(it->second);
    unCounted += dynamic_cast<CFootBotForaging&>(cFootBot.GetControllableEntity().GetController())
                     .GetFoodData()
                     .TotalFoodItems;
  }
  std::ofstream cSummary("foraging_summary.txt", std::ios_base::trunc | std::ios_base::out);
  cSummary << "collected " << m_unCollected << "\ncounted_by_robots " << unCounted
           << "\narrivals_in_nest " << m_unArrivals << "\n";
  LOG << "foraging: " << m_unCollected << " items collected" << std::endl;
}

void CForagingLoopFunctions::Destroy() { m_cOutput.close(); }

REGISTER_LOOP_FUNCTIONS(CForagingLoopFunctions, "foraging_loop_functions")

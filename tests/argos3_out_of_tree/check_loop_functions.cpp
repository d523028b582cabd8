// Loop functions that measure what a user watching the diffusion, flocking
// and synchronization experiments would notice, written against ARGoS's
// interface. Each writes its figures, "name value" per line, to a file in the
// working folder when the experiment ends.
#include <argos3/core/simulator/loop_functions.h>
#include <argos3/plugins/robots/foot-bot/simulator/footbot_entity.h>

#include <fstream>
#include <map>
#include <set>
#include <vector>

using namespace argos;

/* The experiments' walls: 0.1 m thick, centred on x, y = +-2 m */
static const Real WALL_INNER_FACE = 1.95;
static const Real FOOTBOT_RADIUS = 0.085;

/* Centre positions of all foot-bots, by id */
static std::map<std::string, CVector2> Positions(CSpace& c_space) {
  std::map<std::string, CVector2> cPositions;
  CSpace::TMapPerType& tFootBots = c_space.GetEntitiesByType("foot-bot");
  for (CSpace::TMapPerType::iterator it = tFootBots.begin(); it != tFootBots.end(); ++it) {
    CFootBotEntity* pcFootBot = any_cast<CFootBotEntity*>(it->second);
    const CVector3& cPos = pcFootBot->GetEmbodiedEntity().GetOriginAnchor().Position;
    cPositions[it->first] = CVector2(cPos.GetX(), cPos.GetY());
  }
  return cPositions;
}

/* Mean distance from the swarm's centroid */
static Real Dispersion(const std::map<std::string, CVector2>& c_positions) {
  CVector2 cCentroid;
  for (const auto& p : c_positions) cCentroid += p.second;
  cCentroid /= c_positions.size();
  Real fSum = 0;
  for (const auto& p : c_positions) fSum += Distance(p.second, cCentroid);
  return fSum / c_positions.size();
}

/* Diffusion: the smallest gap ever seen between a robot's body and a wall,
   and how spread out the swarm is at the start and at the end. */
class CDiffusionCheck : public CLoopFunctions {
 public:
  virtual void Init(TConfigurationNode& t_tree) {
    m_fMinWallClearance = 1e9;
    m_fMinRobotGap = 1e9;
    m_fInitialDispersion = Dispersion(Positions(GetSpace()));
    m_cPrevious = Positions(GetSpace());
    m_fMaxSpeed = 0;
  }
  virtual void PostStep() {
    const std::map<std::string, CVector2> cPositions = Positions(GetSpace());
    for (const auto& p : cPositions) {
      /* The file runs 10 ticks per second */
      m_fMaxSpeed = Max(m_fMaxSpeed, Distance(p.second, m_cPrevious[p.first]) / 0.1);
      const Real fClearance =
          WALL_INNER_FACE - Max(Abs(p.second.GetX()), Abs(p.second.GetY())) - FOOTBOT_RADIUS;
      m_fMinWallClearance = Min(m_fMinWallClearance, fClearance);
      for (const auto& q : cPositions) {
        if (p.first < q.first) {
          m_fMinRobotGap = Min(m_fMinRobotGap, Distance(p.second, q.second) - 2 * FOOTBOT_RADIUS);
        }
      }
    }
    m_fFinalDispersion = Dispersion(cPositions);
    m_cPrevious = cPositions;
  }
  virtual void PostExperiment() {
    std::ofstream cOut("diffusion.txt");
    cOut << "min_wall_clearance " << m_fMinWallClearance << "\n"
         << "min_robot_gap " << m_fMinRobotGap << "\n"
         << "initial_dispersion " << m_fInitialDispersion << "\n"
         << "final_dispersion " << m_fFinalDispersion << "\n"
         << "dispersion_growth " << m_fFinalDispersion / m_fInitialDispersion << "\n"
         << "max_speed " << m_fMaxSpeed << "\n";
  }

 private:
  Real m_fMinWallClearance, m_fMinRobotGap, m_fInitialDispersion, m_fFinalDispersion;
  Real m_fMaxSpeed;
  std::map<std::string, CVector2> m_cPrevious;
};

/* Flocking: how aligned the headings are (1: all the same) at the start
   and at the end, how far the farthest robot is from the flock's centre,
   and how many robots show green (they hear neighbours). */
class CFlockingCheck : public CLoopFunctions {
 public:
  virtual void Init(TConfigurationNode& t_tree) { m_fInitialPolarization = Polarization(); }
  virtual void PostExperiment() {
    const std::map<std::string, CVector2> cPositions = Positions(GetSpace());
    CVector2 cCentroid;
    for (const auto& p : cPositions) cCentroid += p.second;
    cCentroid /= cPositions.size();
    Real fFarthest = 0;
    for (const auto& p : cPositions) fFarthest = Max(fFarthest, Distance(p.second, cCentroid));
    UInt32 unGreen = 0;
    CSpace::TMapPerType& tFootBots = GetSpace().GetEntitiesByType("foot-bot");
    for (CSpace::TMapPerType::iterator it = tFootBots.begin(); it != tFootBots.end(); ++it) {
      CFootBotEntity* pcFootBot = any_cast<CFootBotEntity*>(it->second);
      if (pcFootBot->GetLEDEquippedEntity().GetLED(0).GetColor() == CColor::GREEN) ++unGreen;
    }
    std::ofstream cOut("flocking.txt");
    cOut << "initial_polarization " << m_fInitialPolarization << "\n"
         << "final_polarization " << Polarization() << "\n"
         << "farthest_from_centre " << fFarthest << "\n"
         << "robots " << cPositions.size() << "\n"
         << "green " << unGreen << "\n"
         << "centre_travelled " << cCentroid.Length() << "\n";
  }

 private:
  Real Polarization() {
    CVector2 cSum;
    UInt32 unCount = 0;
    CSpace::TMapPerType& tFootBots = GetSpace().GetEntitiesByType("foot-bot");
    for (CSpace::TMapPerType::iterator it = tFootBots.begin(); it != tFootBots.end(); ++it) {
      CFootBotEntity* pcFootBot = any_cast<CFootBotEntity*>(it->second);
      CRadians cZ, cY, cX;
      pcFootBot->GetEmbodiedEntity().GetOriginAnchor().Orientation.ToEulerAngles(cZ, cY, cX);
      cSum += CVector2(1.0, cZ);
      ++unCount;
    }
    return cSum.Length() / unCount;
  }

  Real m_fInitialPolarization;
};

/* Synchronization: in the first and in the last period (50 ticks), on how
   many distinct ticks robots flashed (their LEDs red), and how many robots
   flashed in the last period. */
class CSynchronizationCheck : public CLoopFunctions {
 public:
  static const UInt32 PERIOD = 50;

  virtual void PostStep() {
    std::set<std::string> cFlashing;
    CSpace::TMapPerType& tFootBots = GetSpace().GetEntitiesByType("foot-bot");
    for (CSpace::TMapPerType::iterator it = tFootBots.begin(); it != tFootBots.end(); ++it) {
      CFootBotEntity* pcFootBot = any_cast<CFootBotEntity*>(it->second);
      if (pcFootBot->GetLEDEquippedEntity().GetLED(0).GetColor() == CColor::RED) {
        cFlashing.insert(it->first);
      }
    }
    m_vecFlashes.push_back(cFlashing);
  }
  virtual void PostExperiment() {
    std::ofstream cOut("synchronization.txt");
    cOut << "first_period_flash_ticks " << FlashTicks(0) << "\n"
         << "last_period_flash_ticks " << FlashTicks(m_vecFlashes.size() - PERIOD) << "\n"
         << "robots_flashing_last_period " << Flashers(m_vecFlashes.size() - PERIOD) << "\n";
  }

 private:
  UInt32 FlashTicks(size_t un_from) const {
    UInt32 unTicks = 0;
    for (size_t i = un_from; i < un_from + PERIOD; ++i) unTicks += !m_vecFlashes[i].empty();
    return unTicks;
  }
  size_t Flashers(size_t un_from) const {
    std::set<std::string> cAll;
    for (size_t i = un_from; i < un_from + PERIOD; ++i)
      cAll.insert(m_vecFlashes[i].begin(), m_vecFlashes[i].end());
    return cAll.size();
  }

  std::vector<std::set<std::string> > m_vecFlashes;
};

REGISTER_LOOP_FUNCTIONS(CDiffusionCheck, "diffusion_check")
REGISTER_LOOP_FUNCTIONS(CFlockingCheck, "flocking_check")
REGISTER_LOOP_FUNCTIONS(CSynchronizationCheck, "synchronization_check")

// Loop functions of the foraging task, written against ARGoS's interface as
// an ARGoS user writes them: food items lie at random points east of the
// nest; an exploring robot driving over one picks it up, a robot carrying
// one drops it on entering the nest (x < -1 m), and the item reappears
// elsewhere. They colour the floor: grey in the nest, a black disc under each
// item (where the items start: Colony draws the floor once). Writes
// foraging.txt (a row per tick: clock, walking, resting, collected) and, at
// the end, foraging_summary.txt (items collected, as the robots count them
// too, and how many times a robot came to rest in the nest).
#ifndef FORAGING_LOOP_FUNCTIONS_H
#define FORAGING_LOOP_FUNCTIONS_H

#include <argos3/core/simulator/loop_functions.h>
#include <argos3/core/utility/math/range.h>
#include <argos3/core/utility/math/rng.h>

#include <fstream>
#include <map>
#include <string>
#include <vector>

using namespace argos;

class CForagingLoopFunctions : public CLoopFunctions {
 public:
  CForagingLoopFunctions();
  virtual ~CForagingLoopFunctions() {}
  virtual void Init(TConfigurationNode& t_tree);
  virtual CColor GetFloorColor(const CVector2& c_position_on_plane);
  virtual void PreStep();
  virtual void PostExperiment();
  virtual void Destroy();

 private:
  CVector2 RandomFoodPosition();

  CRange<Real> m_cFoodX, m_cFoodY;
  Real m_fPickUpRadius;
  std::vector<CVector2> m_cFoodPos;
  CRandom::CRNG* m_pcRNG;
  std::ofstream m_cOutput;
  UInt32 m_unCollected;
  /* Robots coming to rest in the nest (which they find by its grey floor) */
  std::map<std::string, bool> m_mapWasResting;
  UInt32 m_unArrivals;
};

#endif

// The controller side of a foraging task, written against ARGoS's control
// interface as an ARGoS user writes it. Robots rest in the nest (the grey
// part of the floor, seen by the motor ground sensors), leave it at random to
// explore, and come back to the light above the nest once they carry a food
// item (the loop functions hand items to robots driving over them) or after
// exploring in vain for long enough. A robot back with an item tells the
// resting ones over range-and-bearing, which makes them more eager to leave.
// LEDs: red resting, green exploring, blue returning.
#ifndef FOOTBOT_FORAGING_H
#define FOOTBOT_FORAGING_H

#include <argos3/core/control_interface/ci_controller.h>
#include <argos3/core/utility/math/rng.h>
#include <argos3/core/utility/math/vector2.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_light_sensor.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_motor_ground_sensor.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_proximity_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_differential_steering_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_leds_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_sensor.h>

using namespace argos;

class CFootBotForaging : public CCI_Controller {
 public:
  /* What the loop functions read and write */
  struct SFoodData {
    bool HasFoodItem;
    size_t FoodItemIdx;
    size_t TotalFoodItems;
    SFoodData() : HasFoodItem(false), FoodItemIdx(0), TotalFoodItems(0) {}
  };

  CFootBotForaging();
  virtual ~CFootBotForaging() {}
  virtual void Init(TConfigurationNode& t_node);
  virtual void ControlStep();
  virtual void Reset();
  virtual void Destroy() {}

  bool IsResting() const { return m_eState == STATE_RESTING; }
  bool IsExploring() const { return m_eState == STATE_EXPLORING; }
  SFoodData& GetFoodData() { return m_sFoodData; }

 private:
  enum EState { STATE_RESTING = 0, STATE_EXPLORING, STATE_RETURNING };
  enum EMessage { MESSAGE_NONE = 0, MESSAGE_FOUND_FOOD = 1 };

  bool InNest() const;
  CVector2 AwayFromObstacles(bool& b_blocked) const;
  CVector2 TowardsLight() const;
  void Steer(const CVector2& c_direction);
  void Rest();
  void Explore();
  void Return();

  CCI_DifferentialSteeringActuator* m_pcWheels;
  CCI_LEDsActuator* m_pcLEDs;
  CCI_RangeAndBearingActuator* m_pcRABA;
  CCI_RangeAndBearingSensor* m_pcRABS;
  CCI_FootBotProximitySensor* m_pcProximity;
  CCI_FootBotLightSensor* m_pcLight;
  CCI_FootBotMotorGroundSensor* m_pcGround;
  CRandom::CRNG* m_pcRNG;

  /* Parameters */
  Real m_fDelta;                 /* proximity sum above which a robot avoids */
  Real m_fMaxSpeed;              /* cm/s */
  Real m_fRestToExploreProb;     /* per tick, when rested long enough */
  Real m_fSocialBoost;           /* added to it per success heard */
  Real m_fGiveUpProb;            /* per tick, after exploring in vain long enough */
  UInt32 m_unMinimumRestingTime; /* ticks */
  UInt32 m_unMinimumExploringTime;
  CRange<Real> m_cProbRange;

  EState m_eState;
  bool m_bFoundFood; /* this trip found an item (the loop functions take it in the nest) */
  UInt32 m_unTicksInState;
  Real m_fCurrentRestToExploreProb;
  SFoodData m_sFoodData;
};

#endif

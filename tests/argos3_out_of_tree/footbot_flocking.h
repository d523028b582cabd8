// A foot-bot flocking with its neighbours, written against ARGoS's control
// interface as an ARGoS user writes it. Each robot broadcasts its heading
// (from the positioning sensor) over range-and-bearing; it steers by the sum
// of: a pull towards (or push away from) each neighbour heard, zero at
// `target_distance` cm; the neighbours' mean heading; a push away from
// obstacles seen by the proximity sensors. Its LEDs show green while it hears
// neighbours, red when alone.
#ifndef FOOTBOT_FLOCKING_H
#define FOOTBOT_FLOCKING_H

#include <argos3/core/control_interface/ci_controller.h>
#include <argos3/core/utility/math/vector2.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_proximity_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_differential_steering_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_leds_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_positioning_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_sensor.h>

using namespace argos;

class CFootBotFlocking : public CCI_Controller {
 public:
  struct SFlockingParams {
    Real TargetDistance; /* cm */
    Real Gain;
    Real AlignmentWeight;
    Real AvoidanceWeight;
    void Init(TConfigurationNode& t_node);
  };
  struct SWheelParams {
    Real MaxSpeed;      /* cm/s */
    CRadians SpinAngle; /* beyond this heading error the robot turns on the spot */
    void Init(TConfigurationNode& t_node);
  };

  CFootBotFlocking();
  virtual ~CFootBotFlocking() {}
  virtual void Init(TConfigurationNode& t_node);
  virtual void ControlStep();
  virtual void Reset();
  virtual void Destroy() {}

 private:
  CRadians Heading() const;
  CVector2 NeighbourVector(const CRadians& c_heading, bool& b_heard);
  CVector2 AvoidanceVector();
  void Steer(const CVector2& c_direction);

  CCI_DifferentialSteeringActuator* m_pcWheels;
  CCI_LEDsActuator* m_pcLEDs;
  CCI_RangeAndBearingActuator* m_pcRABA;
  CCI_RangeAndBearingSensor* m_pcRABS;
  CCI_PositioningSensor* m_pcPositioning;
  CCI_FootBotProximitySensor* m_pcProximity;
  SFlockingParams m_sFlocking;
  SWheelParams m_sWheels;
};

#endif

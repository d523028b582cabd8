// A foot-bot wandering without touching anything, written against ARGoS's
// control interface as an ARGoS user writes it (this file is compiled
// unchanged against Colony's compatibility headers).
//
// It drives straight at `velocity` cm/s; when the proximity readings in
// front of it add up to more than `delta`, it turns on the spot away from
// the side they come from until the way ahead is clear.
#ifndef FOOTBOT_DIFFUSION_H
#define FOOTBOT_DIFFUSION_H

#include <argos3/core/control_interface/ci_controller.h>
#include <argos3/plugins/robots/foot-bot/control_interface/ci_footbot_proximity_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_differential_steering_actuator.h>
#include <argos3/plugins/robots/generic/control_interface/ci_leds_actuator.h>

using namespace argos;

class CFootBotDiffusion : public CCI_Controller {
 public:
  CFootBotDiffusion();
  virtual ~CFootBotDiffusion() {}
  virtual void Init(TConfigurationNode& t_node);
  virtual void ControlStep();
  virtual void Reset();
  virtual void Destroy() {}

 private:
  CCI_DifferentialSteeringActuator* m_pcWheels;
  CCI_FootBotProximitySensor* m_pcProximity;
  CCI_LEDsActuator* m_pcLEDs;
  /* Sensors within this angle of the front count as "ahead" */
  CDegrees m_cFrontHalfAngle;
  CRange<CRadians> m_cFront;
  /* Summed reading ahead above which the robot turns */
  Real m_fDelta;
  /* Wheel speed, cm/s */
  Real m_fVelocity;
  /* Which way the current turn goes (+1 left, -1 right, 0 not turning) */
  SInt32 m_nTurning;
};

#endif

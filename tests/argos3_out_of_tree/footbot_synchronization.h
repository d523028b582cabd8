// Foot-bots flashing in unison, like fireflies, written against ARGoS's
// control interface as an ARGoS user writes it. Each robot counts ticks up to
// `period` and then flashes its LEDs red for one tick; it starts at a random
// count. Seeing another robot's flash with its camera pushes its count
// forwards by `coupling` times the count, so that late robots catch up with
// early ones until all flash together.
#ifndef FOOTBOT_SYNCHRONIZATION_H
#define FOOTBOT_SYNCHRONIZATION_H

#include <argos3/core/control_interface/ci_controller.h>
#include <argos3/core/utility/math/rng.h>
#include <argos3/plugins/robots/generic/control_interface/ci_colored_blob_omnidirectional_camera_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_leds_actuator.h>

using namespace argos;

class CFootBotSynchronization : public CCI_Controller {
 public:
  CFootBotSynchronization();
  virtual ~CFootBotSynchronization() {}
  virtual void Init(TConfigurationNode& t_node);
  virtual void ControlStep();
  virtual void Reset();
  virtual void Destroy() {}

 private:
  CCI_LEDsActuator* m_pcLEDs;
  CCI_ColoredBlobOmnidirectionalCameraSensor* m_pcCamera;
  CRandom::CRNG* m_pcRNG;
  UInt32 m_unPeriod;
  Real m_fCoupling;
  UInt32 m_unCount;
};

#endif

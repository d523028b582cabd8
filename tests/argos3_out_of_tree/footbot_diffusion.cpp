#include "footbot_diffusion.h"

#include <argos3/core/utility/configuration/argos_configuration.h>
#include <argos3/core/utility/logging/argos_log.h>
#include <argos3/core/utility/math/vector2.h>

CFootBotDiffusion::CFootBotDiffusion()
    : m_pcWheels(NULL),
      m_pcProximity(NULL),
      m_pcLEDs(NULL),
      m_cFrontHalfAngle(75.0),
      m_fDelta(0.15),
      m_fVelocity(5.0),
      m_nTurning(0) {}

void CFootBotDiffusion::Init(TConfigurationNode& t_node) {
  m_pcWheels = GetActuator<CCI_DifferentialSteeringActuator>("differential_steering");
  m_pcProximity = GetSensor<CCI_FootBotProximitySensor>("footbot_proximity");
  m_pcLEDs = GetActuator<CCI_LEDsActuator>("leds");
  GetNodeAttributeOrDefault(t_node, "front_half_angle", m_cFrontHalfAngle, m_cFrontHalfAngle);
  m_cFront.Set(-ToRadians(m_cFrontHalfAngle), ToRadians(m_cFrontHalfAngle));
  GetNodeAttributeOrDefault(t_node, "delta", m_fDelta, m_fDelta);
  GetNodeAttributeOrDefault(t_node, "velocity", m_fVelocity, m_fVelocity);
  if (m_fVelocity <= 0.0) {
    THROW_ARGOSEXCEPTION("velocity must be positive, got " << m_fVelocity);
  }
  Reset();
}

void CFootBotDiffusion::Reset() {
  m_nTurning = 0;
  m_pcLEDs->SetAllColors(CColor::GREEN);
}

void CFootBotDiffusion::ControlStep() {
  /* Add up what the sensors ahead see, as a vector pointing at it */
  const CCI_FootBotProximitySensor::TReadings& tReadings = m_pcProximity->GetReadings();
  CVector2 cAhead;
  for (size_t i = 0; i < tReadings.size(); ++i) {
    if (m_cFront.WithinMinBoundIncludedMaxBoundIncluded(tReadings[i].Angle)) {
      cAhead += CVector2(tReadings[i].Value, tReadings[i].Angle);
    }
  }
  if (cAhead.Length() <= m_fDelta) {
    /* The way is clear */
    m_nTurning = 0;
    m_pcWheels->SetLinearVelocity(m_fVelocity, m_fVelocity);
    m_pcLEDs->SetSingleColor(12, CColor::GREEN);
    return;
  }
  /* Pick a side once per obstacle: away from where it is */
  if (m_nTurning == 0) {
    m_nTurning = (cAhead.Angle() > CRadians::ZERO) ? -1 : 1;
  }
  m_pcWheels->SetLinearVelocity(-m_nTurning * m_fVelocity, m_nTurning * m_fVelocity);
  m_pcLEDs->SetSingleColor(12, CColor::RED);
}

REGISTER_CONTROLLER(CFootBotDiffusion, "footbot_diffusion_controller")

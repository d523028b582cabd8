#include "footbot_flocking.h"

#include <argos3/core/utility/configuration/argos_configuration.h>
#include <argos3/core/utility/datatypes/byte_array.h>
#include <argos3/core/utility/logging/argos_log.h>

/* Headings travel as 16-bit fractions of a turn */
static const Real HEADING_UNITS = 65536.0;

void CFootBotFlocking::SFlockingParams::Init(TConfigurationNode& t_node) {
  try {
    GetNodeAttribute(t_node, "target_distance", TargetDistance);
    GetNodeAttribute(t_node, "gain", Gain);
    GetNodeAttributeOrDefault(t_node, "alignment", AlignmentWeight, 1.0);
    GetNodeAttributeOrDefault(t_node, "avoidance", AvoidanceWeight, 4.0);
  } catch (CARGoSException& ex) {
    THROW_ARGOSEXCEPTION_NESTED("Error initializing the flocking parameters.", ex);
  }
}

void CFootBotFlocking::SWheelParams::Init(TConfigurationNode& t_node) {
  try {
    GetNodeAttribute(t_node, "max_speed", MaxSpeed);
    CDegrees cSpin(60.0);
    GetNodeAttributeOrDefault(t_node, "spin_angle", cSpin, cSpin);
    SpinAngle = ToRadians(cSpin);
  } catch (CARGoSException& ex) {
    THROW_ARGOSEXCEPTION_NESTED("Error initializing the wheel parameters.", ex);
  }
}

CFootBotFlocking::CFootBotFlocking()
    : m_pcWheels(NULL),
      m_pcLEDs(NULL),
      m_pcRABA(NULL),
      m_pcRABS(NULL),
      m_pcPositioning(NULL),
      m_pcProximity(NULL) {}

void CFootBotFlocking::Init(TConfigurationNode& t_node) {
  m_pcWheels = GetActuator<CCI_DifferentialSteeringActuator>("differential_steering");
  m_pcLEDs = GetActuator<CCI_LEDsActuator>("leds");
  m_pcRABA = GetActuator<CCI_RangeAndBearingActuator>("range_and_bearing");
  m_pcRABS = GetSensor<CCI_RangeAndBearingSensor>("range_and_bearing");
  m_pcPositioning = GetSensor<CCI_PositioningSensor>("positioning");
  m_pcProximity = GetSensor<CCI_FootBotProximitySensor>("footbot_proximity");
  try {
    m_sFlocking.Init(GetNode(t_node, "flocking"));
    m_sWheels.Init(GetNode(t_node, "wheel_turning"));
  } catch (CARGoSException& ex) {
    THROW_ARGOSEXCEPTION_NESTED("Error parsing the parameters of robot " << GetId(), ex);
  }
  if (m_pcRABA->GetSize() < 2) {
    THROW_ARGOSEXCEPTION("the range-and-bearing payload must hold 2 bytes, it holds "
                         << m_pcRABA->GetSize());
  }
  Reset();
}

void CFootBotFlocking::Reset() {
  m_pcLEDs->SetAllColors(CColor::RED);
  m_pcRABA->ClearData();
}

CRadians CFootBotFlocking::Heading() const {
  CRadians cZ, cY, cX;
  m_pcPositioning->GetReading().Orientation.ToEulerAngles(cZ, cY, cX);
  return cZ;
}

CVector2 CFootBotFlocking::NeighbourVector(const CRadians& c_heading, bool& b_heard) {
  const CCI_RangeAndBearingSensor::TReadings& tPackets = m_pcRABS->GetReadings();
  CVector2 cCohesion, cAlignment;
  for (size_t i = 0; i < tPackets.size(); ++i) {
    /* Spring towards the target distance, saturated */
    Real fPull = m_sFlocking.Gain * (tPackets[i].Range - m_sFlocking.TargetDistance) /
                 m_sFlocking.TargetDistance;
    fPull = Max<Real>(-1.0, Min<Real>(1.0, fPull));
    cCohesion += CVector2(fPull, tPackets[i].HorizontalBearing);
    /* The neighbour's heading, in this robot's frame */
    CByteArray cData(tPackets[i].Data);
    UInt16 unHeading;
    cData >> unHeading;
    CRadians cTheirs(unHeading / HEADING_UNITS * CRadians::TWO_PI.GetValue());
    cAlignment += CVector2(1.0, NormalizedDifference(cTheirs, c_heading));
  }
  b_heard = !tPackets.empty();
  if (!b_heard) return CVector2();
  cCohesion /= tPackets.size();
  cAlignment /= tPackets.size();
  return cCohesion + m_sFlocking.AlignmentWeight * cAlignment;
}

CVector2 CFootBotFlocking::AvoidanceVector() {
  const CCI_FootBotProximitySensor::TReadings& tReadings = m_pcProximity->GetReadings();
  CVector2 cObstacle;
  for (size_t i = 0; i < tReadings.size(); ++i) {
    cObstacle += CVector2(tReadings[i].Value, tReadings[i].Angle);
  }
  return -m_sFlocking.AvoidanceWeight * cObstacle;
}

void CFootBotFlocking::Steer(const CVector2& c_direction) {
  if (c_direction.SquareLength() < 1e-12) {
    m_pcWheels->SetLinearVelocity(m_sWheels.MaxSpeed, m_sWheels.MaxSpeed);
    return;
  }
  const CRadians cError = c_direction.Angle();
  const Real fTurn = cError.GetValue() / m_sWheels.SpinAngle.GetValue();
  const Real fForward = Abs(cError) < m_sWheels.SpinAngle ? m_sWheels.MaxSpeed * Cos(cError) : 0.0;
  const Real fRotation = 0.5 * m_sWheels.MaxSpeed * Max<Real>(-1.0, Min<Real>(1.0, fTurn));
  m_pcWheels->SetLinearVelocity(fForward - fRotation, fForward + fRotation);
}

void CFootBotFlocking::ControlStep() {
  const CRadians cHeading = Heading();
  /* Tell the others where this robot heads */
  CRadians cUnsigned(cHeading);
  cUnsigned.UnsignedNormalize();
  CByteArray cMessage;
  cMessage << static_cast<UInt16>(
      static_cast<UInt32>(cUnsigned.GetValue() / CRadians::TWO_PI.GetValue() * HEADING_UNITS) %
      65536);
  while (cMessage.Size() < m_pcRABA->GetSize()) cMessage << static_cast<UInt8>(0);
  m_pcRABA->SetData(cMessage);

  bool bHeard;
  CVector2 cDirection =
      CVector2(1.0, CRadians::ZERO) + NeighbourVector(cHeading, bHeard) + AvoidanceVector();
  Steer(cDirection);
  m_pcLEDs->SetAllColors(bHeard ? CColor::GREEN : CColor::RED);
}

REGISTER_CONTROLLER(CFootBotFlocking, "footbot_flocking_controller")

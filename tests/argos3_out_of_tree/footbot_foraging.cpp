#include "footbot_foraging.h"

#include <argos3/core/utility/configuration/argos_configuration.h>
#include <argos3/core/utility/logging/argos_log.h>

CFootBotForaging::CFootBotForaging()
    : m_pcWheels(NULL),
      m_pcLEDs(NULL),
      m_pcRABA(NULL),
      m_pcRABS(NULL),
      m_pcProximity(NULL),
      m_pcLight(NULL),
      m_pcGround(NULL),
      m_pcRNG(NULL),
      m_cProbRange(0.0, 1.0),
      m_eState(STATE_RESTING),
      m_bFoundFood(false),
      m_unTicksInState(0),
      m_fCurrentRestToExploreProb(0) {}

void CFootBotForaging::Init(TConfigurationNode& t_node) {
  try {
    m_pcWheels = GetActuator<CCI_DifferentialSteeringActuator>("differential_steering");
    m_pcLEDs = GetActuator<CCI_LEDsActuator>("leds");
    m_pcRABA = GetActuator<CCI_RangeAndBearingActuator>("range_and_bearing");
    m_pcRABS = GetSensor<CCI_RangeAndBearingSensor>("range_and_bearing");
    m_pcProximity = GetSensor<CCI_FootBotProximitySensor>("footbot_proximity");
    m_pcLight = GetSensor<CCI_FootBotLightSensor>("footbot_light");
    m_pcGround = GetSensor<CCI_FootBotMotorGroundSensor>("footbot_motor_ground");
    TConfigurationNode& tDiffusion = GetNode(t_node, "diffusion");
    GetNodeAttribute(tDiffusion, "delta", m_fDelta);
    GetNodeAttribute(GetNode(t_node, "wheel_turning"), "max_speed", m_fMaxSpeed);
    TConfigurationNode& tState = GetNode(t_node, "state");
    GetNodeAttribute(tState, "rest_to_explore_prob", m_fRestToExploreProb);
    GetNodeAttribute(tState, "social_boost", m_fSocialBoost);
    GetNodeAttribute(tState, "give_up_prob", m_fGiveUpProb);
    GetNodeAttribute(tState, "minimum_resting_time", m_unMinimumRestingTime);
    GetNodeAttribute(tState, "minimum_exploring_time", m_unMinimumExploringTime);
  } catch (CARGoSException& ex) {
    THROW_ARGOSEXCEPTION_NESTED(
        "Error initializing the foot-bot foraging controller for robot \"" << GetId() << "\"", ex);
  }
  m_pcRNG = CRandom::CreateRNG("argos");
  Reset();
}

void CFootBotForaging::Reset() {
  m_eState = STATE_RESTING;
  m_bFoundFood = false;
  /* Ready to leave at once: no one waits for nothing at the start */
  m_unTicksInState = m_unMinimumRestingTime;
  m_fCurrentRestToExploreProb = m_fRestToExploreProb;
  m_sFoodData = SFoodData();
  m_pcLEDs->SetAllColors(CColor::RED);
  m_pcRABA->ClearData();
}

bool CFootBotForaging::InNest() const {
  /* The nest is grey: both back-right and front-right sensors on mid-grey */
  const CCI_FootBotMotorGroundSensor::TReadings& tGround = m_pcGround->GetReadings();
  return tGround[2].Value > 0.25 && tGround[2].Value < 0.75 && tGround[3].Value > 0.25 &&
         tGround[3].Value < 0.75;
}

CVector2 CFootBotForaging::AwayFromObstacles(bool& b_blocked) const {
  const CCI_FootBotProximitySensor::TReadings& tReadings = m_pcProximity->GetReadings();
  CVector2 cObstacle;
  for (size_t i = 0; i < tReadings.size(); ++i) {
    cObstacle += CVector2(tReadings[i].Value, tReadings[i].Angle);
  }
  b_blocked = cObstacle.Length() > m_fDelta;
  if (!b_blocked) return CVector2::X;
  cObstacle.Normalize();
  return -cObstacle;
}

CVector2 CFootBotForaging::TowardsLight() const {
  const CCI_FootBotLightSensor::TReadings& tReadings = m_pcLight->GetReadings();
  CVector2 cLight;
  for (size_t i = 0; i < tReadings.size(); ++i) {
    cLight += CVector2(tReadings[i].Value, tReadings[i].Angle);
  }
  if (cLight.Length() == 0.0) return CVector2();
  return CVector2(1.0, cLight.Angle());
}

void CFootBotForaging::Steer(const CVector2& c_direction) {
  const CRadians cError = c_direction.Angle();
  if (Abs(cError) > CRadians::PI_OVER_THREE) {
    /* Turn on the spot */
    const Real fSpin = (cError > CRadians::ZERO) ? m_fMaxSpeed : -m_fMaxSpeed;
    m_pcWheels->SetLinearVelocity(-0.5 * fSpin, 0.5 * fSpin);
    return;
  }
  const Real fTurn = cError / CRadians::PI_OVER_THREE;
  m_pcWheels->SetLinearVelocity(m_fMaxSpeed * (1.0 - Max<Real>(0.0, fTurn)),
                                m_fMaxSpeed * (1.0 + Min<Real>(0.0, fTurn)));
}

void CFootBotForaging::Rest() {
  m_pcWheels->SetLinearVelocity(0.0, 0.0);
  /* Successes heard make leaving more likely */
  const CCI_RangeAndBearingSensor::TReadings& tPackets = m_pcRABS->GetReadings();
  for (size_t i = 0; i < tPackets.size(); ++i) {
    if (tPackets[i].Data[0] == MESSAGE_FOUND_FOOD) {
      m_fCurrentRestToExploreProb += m_fSocialBoost;
      m_cProbRange.TruncValue(m_fCurrentRestToExploreProb);
    }
  }
  if (m_unTicksInState >= m_unMinimumRestingTime &&
      m_pcRNG->Uniform(m_cProbRange) < m_fCurrentRestToExploreProb) {
    m_eState = STATE_EXPLORING;
    m_unTicksInState = 0;
    m_pcLEDs->SetAllColors(CColor::GREEN);
    m_pcRABA->SetData(0, MESSAGE_NONE);
  }
}

void CFootBotForaging::Explore() {
  if (m_sFoodData.HasFoodItem ||
      (m_unTicksInState > m_unMinimumExploringTime && m_pcRNG->Bernoulli(m_fGiveUpProb))) {
    m_eState = STATE_RETURNING;
    m_bFoundFood = m_sFoodData.HasFoodItem;
    m_unTicksInState = 0;
    m_pcLEDs->SetAllColors(CColor::BLUE);
    return;
  }
  bool bBlocked;
  CVector2 cDirection = AwayFromObstacles(bBlocked);
  /* Leave the nest: away from its light */
  if (!bBlocked && InNest()) cDirection -= TowardsLight();
  /* Wander a little */
  cDirection += CVector2(0.3, m_pcRNG->Uniform(CRange<CRadians>(-CRadians::PI, CRadians::PI)));
  Steer(cDirection);
}

void CFootBotForaging::Return() {
  if (InNest()) {
    m_eState = STATE_RESTING;
    m_unTicksInState = 0;
    m_fCurrentRestToExploreProb = m_fRestToExploreProb;
    m_pcLEDs->SetAllColors(CColor::RED);
    m_pcRABA->SetData(0, m_bFoundFood ? MESSAGE_FOUND_FOOD : MESSAGE_NONE);
    m_pcWheels->SetLinearVelocity(0.0, 0.0);
    return;
  }
  bool bBlocked;
  const CVector2 cAvoid = AwayFromObstacles(bBlocked);
  Steer(bBlocked ? cAvoid + TowardsLight() : TowardsLight());
}

void CFootBotForaging::ControlStep() {
  ++m_unTicksInState;
  switch (m_eState) {
    case STATE_RESTING:
      Rest();
      break;
    case STATE_EXPLORING:
      Explore();
      break;
    case STATE_RETURNING:
      Return();
      break;
    default:
      LOGERR << "robot " << GetId() << " is in an unknown state" << std::endl;
  }
}

REGISTER_CONTROLLER(CFootBotForaging, "footbot_foraging_controller")

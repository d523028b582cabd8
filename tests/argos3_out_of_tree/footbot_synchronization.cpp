#include "footbot_synchronization.h"

#include <argos3/core/utility/configuration/argos_configuration.h>

CFootBotSynchronization::CFootBotSynchronization()
    : m_pcLEDs(NULL),
      m_pcCamera(NULL),
      m_pcRNG(NULL),
      m_unPeriod(50),
      m_fCoupling(0.1),
      m_unCount(0) {}

void CFootBotSynchronization::Init(TConfigurationNode& t_node) {
  m_pcLEDs = GetActuator<CCI_LEDsActuator>("leds");
  m_pcCamera =
      GetSensor<CCI_ColoredBlobOmnidirectionalCameraSensor>("colored_blob_omnidirectional_camera");
  GetNodeAttributeOrDefault(t_node, "period", m_unPeriod, m_unPeriod);
  GetNodeAttributeOrDefault(t_node, "coupling", m_fCoupling, m_fCoupling);
  m_pcRNG = CRandom::CreateRNG("argos");
  m_pcCamera->Enable();
  Reset();
}

void CFootBotSynchronization::Reset() {
  m_unCount = m_pcRNG->Uniform(CRange<UInt32>(0, m_unPeriod));
  m_pcLEDs->SetAllColors(CColor::BLACK);
}

void CFootBotSynchronization::ControlStep() {
  const CCI_ColoredBlobOmnidirectionalCameraSensor::SReadings& sBlobs = m_pcCamera->GetReadings();
  bool bFlashSeen = false;
  for (size_t i = 0; i < sBlobs.BlobList.size() && !bFlashSeen; ++i) {
    bFlashSeen = sBlobs.BlobList[i]->Color == CColor::RED;
  }
  m_unCount += 1;
  if (bFlashSeen) {
    m_unCount += static_cast<UInt32>(m_fCoupling * m_unCount);
  }
  if (m_unCount >= m_unPeriod) {
    m_pcLEDs->SetAllColors(CColor::RED);
    m_unCount = 0;
  } else {
    m_pcLEDs->SetAllColors(CColor::BLACK);
  }
}

REGISTER_CONTROLLER(CFootBotSynchronization, "footbot_synchronization_controller")

// The ARGoS controller host and the device adapters: each adapter is an
// ARGoS control-interface class over one of Colony's devices, converting
// units at the boundary (Colony is SI; ARGoS's interface uses cm for wheel
// speeds, range-and-bearing ranges, blob distances and ground offsets).
#include "argos3/colony/controller_host.h"

#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <span>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_base_ground_sensor.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_light_sensor.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_motor_ground_sensor.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_proximity_sensor.h"
#include "argos3/plugins/robots/generic/control_interface/ci_colored_blob_omnidirectional_camera_sensor.h"
#include "argos3/plugins/robots/generic/control_interface/ci_differential_steering_actuator.h"
#include "argos3/plugins/robots/generic/control_interface/ci_differential_steering_sensor.h"
#include "argos3/plugins/robots/generic/control_interface/ci_leds_actuator.h"
#include "argos3/plugins/robots/generic/control_interface/ci_positioning_sensor.h"
#include "argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_actuator.h"
#include "argos3/plugins/robots/generic/control_interface/ci_range_and_bearing_sensor.h"
#include "configuration_tree.h"
#include "core/log.h"
#include "sensors/ground/ground.h"
#include "sensors/light/light.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"
#include "sensors/positioning/positioning.h"
#include "sensors/proximity/proximity.h"
#include "sensors/range_and_bearing/range_and_bearing.h"
#include "sensors/wheel_encoders/wheel_encoders.h"

namespace argos {

namespace {
constexpr Real kCmPerM = 100.0;
}  // namespace

// ---------------------------------------------------------------------------
// CCI_Controller

CCI_Controller::~CCI_Controller() = default;

const std::string& CCI_Controller::GetId() const {
  static const std::string kNone;
  return host_ ? host_->id() : kNone;
}

CCI_Sensor* CCI_Controller::FindSensor(const std::string& label, const std::type_info& wanted) {
  if (host_ == nullptr) THROW_ARGOSEXCEPTION("GetSensor(\"" << label << "\") called before Init");
  return host_->FindSensor(label, wanted);
}

CCI_Actuator* CCI_Controller::FindActuator(const std::string& label) {
  if (host_ == nullptr) THROW_ARGOSEXCEPTION("GetActuator(\"" << label << "\") called before Init");
  return host_->FindActuator(label);
}

bool CCI_Controller::HasSensor(const std::string& label) const {
  return host_ && host_->HasDevice(label, true);
}

bool CCI_Controller::HasActuator(const std::string& label) const {
  return host_ && host_->HasDevice(label, false);
}

namespace internal {
namespace {

// ---------------------------------------------------------------------------
// Sensor adapters: an ARGoS sensor interface over a Colony sensor, read
// again before each control step.

class SensorAdapter {
 public:
  virtual ~SensorAdapter() = default;
  virtual void Update() = 0;
  virtual CCI_Sensor& sensor() = 0;
};

// A ring of (value, angle) readings: the proximity and light sensors.
template <class Interface, class Source>
class RingAdapter final : public Interface, public SensorAdapter {
 public:
  explicit RingAdapter(const Source& source) : source_(source) { Update(); }
  void Update() override {
    const auto& in = source_.readings();
    this->readings_.resize(in.size());
    for (size_t i = 0; i < in.size(); ++i)
      this->readings_[i] = {in[i].value, CRadians(in[i].angle)};
  }
  CCI_Sensor& sensor() override { return *this; }

 private:
  const Source& source_;
};
using ProximityAdapter = RingAdapter<CCI_FootBotProximitySensor, colony::ProximitySensor>;
using LightAdapter = RingAdapter<CCI_FootBotLightSensor, colony::LightSensor>;

// For each of ARGoS's ground sensors (offsets in cm), the index of Colony's
// ground sensor nearest in direction.
template <typename Readings>
void MatchGround(const Readings& argos_sensors,
                 const std::vector<colony::GroundSensor::Reading>& in,
                 std::vector<size_t>& nearest) {
  nearest.assign(argos_sensors.size(), 0);
  for (size_t j = 0; j < argos_sensors.size(); ++j) {
    const CRadians direction = argos_sensors[j].Offset.Angle();
    Real best = 10;
    for (size_t i = 0; i < in.size(); ++i) {
      const Real gap = Abs(NormalizedDifference(CRadians(in[i].angle), direction).GetValue());
      if (gap < best) {
        best = gap;
        nearest[j] = i;
      }
    }
  }
}

// ARGoS's ground sensors, each reading Colony's ground sensor nearest in
// direction: the motor ground's grey levels, or the base ground's black and
// white (0 below mid-grey, 1 from it).
template <class Interface, bool kBlackOrWhite>
class GroundAdapter final : public Interface, public SensorAdapter {
 public:
  explicit GroundAdapter(const colony::GroundSensor& source) : source_(source) { Update(); }
  void Update() override {
    const auto& in = source_.readings();
    if (in.empty()) return;
    auto& out = this->readings_;
    if (matched_size_ != in.size()) {
      MatchGround(out, in, nearest_);
      matched_size_ = in.size();
    }
    for (size_t j = 0; j < out.size(); ++j) {
      const float v = in[nearest_[j]].value;
      out[j].Value = kBlackOrWhite ? (v < 0.5f ? 0.0 : 1.0) : v;
    }
  }
  CCI_Sensor& sensor() override { return *this; }

 private:
  const colony::GroundSensor& source_;
  std::vector<size_t> nearest_;
  size_t matched_size_ = 0;
};
using MotorGroundAdapter = GroundAdapter<CCI_FootBotMotorGroundSensor, false>;
using BaseGroundAdapter = GroundAdapter<CCI_FootBotBaseGroundSensor, true>;

class CameraAdapter final : public CCI_ColoredBlobOmnidirectionalCameraSensor,
                            public SensorAdapter {
 public:
  explicit CameraAdapter(const colony::OmnidirectionalCamera& source) : source_(source) {
    Disable();
  }
  void Update() override {
    if (IsDisabled()) return;
    ++readings_.Counter;
    const auto& in = source_.blobs();
    blobs_.resize(in.size());
    readings_.BlobList.resize(in.size());
    for (size_t i = 0; i < in.size(); ++i) {
      blobs_[i] = SBlob(CColor(in[i].red, in[i].green, in[i].blue), CRadians(in[i].bearing),
                        in[i].distance * kCmPerM);
      readings_.BlobList[i] = &blobs_[i];
    }
  }
  CCI_Sensor& sensor() override { return *this; }

 private:
  const colony::OmnidirectionalCamera& source_;
  std::vector<SBlob> blobs_;
};

class RangeAndBearingSensorAdapter final : public CCI_RangeAndBearingSensor, public SensorAdapter {
 public:
  explicit RangeAndBearingSensorAdapter(const colony::RangeAndBearingSensor& source)
      : source_(source) {
    Update();
  }
  void Update() override {
    const auto& in = source_.packets();
    readings_.resize(in.size());
    for (size_t i = 0; i < in.size(); ++i) {
      SPacket& p = readings_[i];
      p.Range = in[i].range * kCmPerM;
      p.HorizontalBearing = CRadians(in[i].bearing);
      p.VerticalBearing = CRadians(in[i].elevation);
      p.Data.Resize(in[i].data.size());
      if (!in[i].data.empty()) std::memcpy(p.Data.ToCArray(), in[i].data.data(), in[i].data.size());
    }
  }
  CCI_Sensor& sensor() override { return *this; }

 private:
  const colony::RangeAndBearingSensor& source_;
};

class PositioningAdapter final : public CCI_PositioningSensor, public SensorAdapter {
 public:
  explicit PositioningAdapter(const colony::PositioningSensor& source) : source_(source) {
    Update();
  }
  void Update() override {
    reading_.Position.Set(source_.x(), source_.y(), source_.z());
    reading_.Orientation.FromAngleAxis(CRadians(source_.yaw()), CVector3::Z);
  }
  CCI_Sensor& sensor() override { return *this; }

 private:
  const colony::PositioningSensor& source_;
};

class EncodersAdapter final : public CCI_DifferentialSteeringSensor, public SensorAdapter {
 public:
  explicit EncodersAdapter(const colony::WheelEncoders& source) : source_(source) { Update(); }
  void Update() override {
    reading_.CoveredDistanceLeftWheel = source_.distance_left() * kCmPerM;
    reading_.CoveredDistanceRightWheel = source_.distance_right() * kCmPerM;
    reading_.WheelAxisLength = source_.wheel_base() * kCmPerM;
  }
  CCI_Sensor& sensor() override { return *this; }

 private:
  const colony::WheelEncoders& source_;
};

// ---------------------------------------------------------------------------
// Actuator adapters: an ARGoS actuator interface writing to a Colony
// actuator right away (Colony applies it at the next tick's act phase).

class WheelsAdapter final : public CCI_DifferentialSteeringActuator {
 public:
  explicit WheelsAdapter(colony::DifferentialSteering& target) : target_(target) {}
  // cm/s -> m/s. No clamping here: the actuator handles speeds beyond the
  // robot's.
  void SetLinearVelocity(Real left, Real right) override {
    target_.SetLinearVelocity(left / kCmPerM, right / kCmPerM);
  }

 private:
  colony::DifferentialSteering& target_;
};

class LedsAdapter final : public CCI_LEDsActuator {
 public:
  explicit LedsAdapter(colony::Leds& target) : target_(target) {
    settings_.resize(target.count());
    for (size_t i = 0; i < target.count(); ++i) settings_[i] = FromColony(target.colors()[i]);
  }
  void SetSingleColor(UInt32 index, const CColor& color) override {
    Check(index);
    settings_[index] = color;
    target_.SetSingleColor(index, ToColony(color));
  }
  void SetAllColors(const CColor& color) override {
    for (auto& s : settings_) s = color;
    target_.SetAllColors(ToColony(color));
  }
  void SetAllColors(const TSettings& colors) override {
    if (colors.size() != settings_.size()) {
      THROW_ARGOSEXCEPTION("CCI_LEDsActuator::SetAllColors: " << colors.size()
                                                              << " colours given for "
                                                              << settings_.size() << " LEDs");
    }
    for (size_t i = 0; i < colors.size(); ++i) SetSingleColor(static_cast<UInt32>(i), colors[i]);
  }
  void SetSingleIntensity(UInt32 index, UInt8 intensity) override {
    Check(index);
    CColor color = settings_[index];
    color.SetAlpha(intensity);
    SetSingleColor(index, color);
  }
  void SetAllIntensities(UInt8 intensity) override {
    for (size_t i = 0; i < settings_.size(); ++i)
      SetSingleIntensity(static_cast<UInt32>(i), intensity);
  }

 private:
  void Check(UInt32 index) const {
    if (index >= settings_.size()) {
      THROW_ARGOSEXCEPTION("CCI_LEDsActuator: LED " << index << " does not exist; this robot has "
                                                    << settings_.size() << " (0.."
                                                    << settings_.size() - 1 << ")");
    }
  }
  static colony::Color ToColony(const CColor& c) {
    return {c.GetRed(), c.GetGreen(), c.GetBlue(), c.GetAlpha()};
  }
  static CColor FromColony(const colony::Color& c) { return CColor(c.r, c.g, c.b, c.a); }

  colony::Leds& target_;
};

class RangeAndBearingActuatorAdapter final : public CCI_RangeAndBearingActuator {
 public:
  explicit RangeAndBearingActuatorAdapter(colony::RangeAndBearingActuator& target)
      : target_(target) {
    data_.Resize(target.size());
  }
  void SetData(const CByteArray& data) override {
    if (data.Size() != data_.Size()) {
      THROW_ARGOSEXCEPTION(
          "CCI_RangeAndBearingActuator::SetData(): data size does not match, "
          "expected "
          << data_.Size() << " (data_size in the experiment file), got " << data.Size());
    }
    data_ = data;
    Send();
  }
  void SetData(size_t index, UInt8 value) override {
    if (index >= data_.Size()) {
      THROW_ARGOSEXCEPTION("CCI_RangeAndBearingActuator::SetData(): byte "
                           << index << " does not exist; the payload has " << data_.Size()
                           << " bytes (data_size in the experiment file)");
    }
    data_[index] = value;
    target_.SetByte(index, value);
  }
  void ClearData() override {
    data_.Zero();
    Send();
  }

 private:
  void Send() { target_.SetData(std::span<const uint8_t>(data_.ToCArray(), data_.Size())); }

  colony::RangeAndBearingActuator& target_;
};

// ARGoS's device names and the Colony device each stands for, so that an
// ARGoS controller finds its devices in a file written with Colony's names.
const std::map<std::string, std::string, std::less<>> kColonySensorName = {
    {"footbot_proximity", "proximity"},
    {"footbot_light", "light"},
    {"footbot_motor_ground", "ground"},
    {"footbot_base_ground", "ground"},
    {"colored_blob_omnidirectional_camera", "omnidirectional_camera"},
    {"differential_steering", "wheel_encoders"},
};

enum class SensorKind {
  kProximity,
  kLight,
  kMotorGround,
  kBaseGround,
  kCamera,
  kRab,
  kPositioning,
  kEncoders
};

const char* kProvidedSensors =
    "footbot_proximity (proximity), footbot_light (light), footbot_motor_ground and "
    "footbot_base_ground (ground), colored_blob_omnidirectional_camera (omnidirectional_camera), "
    "range_and_bearing, positioning, differential_steering (wheel_encoders)";
const char* kProvidedActuators = "differential_steering, leds, range_and_bearing";

}  // namespace

struct ControllerHost::Devices {
  struct SensorEntry {
    size_t index;
    SensorKind kind;
    std::unique_ptr<SensorAdapter> adapter;
  };
  struct ActuatorEntry {
    size_t index;
    std::unique_ptr<CCI_Actuator> adapter;
  };
  std::vector<SensorEntry> sensors;
  std::vector<ActuatorEntry> actuators;
};

namespace {

// The index of the device declared as `label`: by its element name, by the
// Colony device it stands for, or by ARGoS's name of a Colony device.
std::optional<size_t> FindDevice(const std::string& label, const colony::DeviceLabels& labels,
                                 bool sensor) {
  if (!sensor) return labels.ActuatorIndex(label);
  if (auto i = labels.SensorIndex(label)) return i;
  if (auto it = kColonySensorName.find(label); it != kColonySensorName.end())
    return labels.SensorIndex(it->second);
  return std::nullopt;
}

std::string Declared(const std::vector<std::string>& labels) {
  std::string out;
  for (const auto& l : labels) out += (out.empty() ? "" : ", ") + l;
  return out.empty() ? "none" : out;
}

}  // namespace

ControllerHost::ControllerHost(Factory factory)
    : factory_(factory), devices_(std::make_unique<Devices>()) {}

ControllerHost::~ControllerHost() = default;

void ControllerHost::Init(const colony::Params& params) {
  OwnerScope scope(this);
  user_ = factory_();
  user_->host_ = this;
  bool first_reader = false;
  TConfigurationNode tree = BuildConfigurationTree("params", TakeParameters(params, first_reader));
  try {
    user_->Init(tree);
  } catch (const CARGoSException& e) {
    if (e.parameter().empty()) throw;
    throw ToParamError(e, tree);
  }
  if (!first_reader) return;
  const CCI_Controller& user = *user_;
  for (const auto& name : UnreadAttributes(tree)) {
    colony::LogWarning("ARGoS controller " + TypeName(typeid(user)) + " does not read parameter '" +
                       name + "' (ignored)");
  }
}

void ControllerHost::ControlStep() {
  for (auto& s : devices_->sensors) s.adapter->Update();
  OwnerScope scope(this);
  user_->ControlStep();
}

void ControllerHost::Reset() {
  if (!user_) return;
  OwnerScope scope(this);
  user_->Reset();
}

void ControllerHost::Destroy() {
  if (!user_) return;
  OwnerScope scope(this);
  user_->Destroy();
}

void ControllerHost::Keep(std::unique_ptr<CRandom::CRNG> rng) { rngs_.push_back(std::move(rng)); }

bool ControllerHost::HasDevice(const std::string& label, bool sensor) const {
  const auto& table = devices();
  return FindDevice(label, *table.labels, sensor).has_value();
}

CCI_Sensor* ControllerHost::FindSensor(const std::string& label, const std::type_info& wanted) {
  const auto& table = devices();
  const auto index = FindDevice(label, *table.labels, true);
  if (!index) {
    THROW_ARGOSEXCEPTION("Unknown sensor type " << label
                                                << " requested in controller. Did you add it to "
                                                   "the XML file? Declared: "
                                                << Declared(*table.labels->sensor_labels));
  }
  colony::Sensor* device = table.sensors[*index];
  // What the controller gets: fixed by the Colony device, except for the
  // ground sensor, which serves both of the foot-bot's ground interfaces.
  std::optional<SensorKind> kind;
  if (dynamic_cast<colony::ProximitySensor*>(device)) kind = SensorKind::kProximity;
  if (dynamic_cast<colony::LightSensor*>(device)) kind = SensorKind::kLight;
  if (dynamic_cast<colony::GroundSensor*>(device)) {
    const bool base = wanted == typeid(CCI_FootBotBaseGroundSensor) ||
                      (wanted != typeid(CCI_FootBotMotorGroundSensor) &&
                       (*table.labels->sensor_labels)[*index] == "footbot_base_ground");
    kind = base ? SensorKind::kBaseGround : SensorKind::kMotorGround;
  }
  if (dynamic_cast<colony::OmnidirectionalCamera*>(device)) kind = SensorKind::kCamera;
  if (dynamic_cast<colony::RangeAndBearingSensor*>(device)) kind = SensorKind::kRab;
  if (dynamic_cast<colony::PositioningSensor*>(device)) kind = SensorKind::kPositioning;
  if (dynamic_cast<colony::WheelEncoders*>(device)) kind = SensorKind::kEncoders;
  if (!kind) {
    THROW_ARGOSEXCEPTION("Sensor " << label
                                   << " has no ARGoS control interface in Colony's "
                                      "compatibility layer; provided: "
                                   << kProvidedSensors);
  }
  for (auto& s : devices_->sensors)
    if (s.index == *index && s.kind == *kind) return &s.adapter->sensor();

  std::unique_ptr<SensorAdapter> adapter;
  switch (*kind) {
    case SensorKind::kProximity:
      adapter = std::make_unique<ProximityAdapter>(static_cast<colony::ProximitySensor&>(*device));
      break;
    case SensorKind::kLight:
      adapter = std::make_unique<LightAdapter>(static_cast<colony::LightSensor&>(*device));
      break;
    case SensorKind::kMotorGround:
      adapter = std::make_unique<MotorGroundAdapter>(static_cast<colony::GroundSensor&>(*device));
      break;
    case SensorKind::kBaseGround:
      adapter = std::make_unique<BaseGroundAdapter>(static_cast<colony::GroundSensor&>(*device));
      break;
    case SensorKind::kCamera:
      adapter =
          std::make_unique<CameraAdapter>(static_cast<colony::OmnidirectionalCamera&>(*device));
      break;
    case SensorKind::kRab:
      adapter = std::make_unique<RangeAndBearingSensorAdapter>(
          static_cast<colony::RangeAndBearingSensor&>(*device));
      break;
    case SensorKind::kPositioning:
      adapter =
          std::make_unique<PositioningAdapter>(static_cast<colony::PositioningSensor&>(*device));
      break;
    case SensorKind::kEncoders:
      adapter = std::make_unique<EncodersAdapter>(static_cast<colony::WheelEncoders&>(*device));
      break;
  }
  CCI_Sensor* result = &adapter->sensor();
  devices_->sensors.push_back({*index, *kind, std::move(adapter)});
  return result;
}

CCI_Actuator* ControllerHost::FindActuator(const std::string& label) {
  const auto& table = devices();
  const auto index = FindDevice(label, *table.labels, false);
  if (!index) {
    THROW_ARGOSEXCEPTION("Unknown actuator type " << label
                                                  << " requested in controller. Did you add it "
                                                     "to the XML file? Declared: "
                                                  << Declared(*table.labels->actuator_labels));
  }
  for (auto& a : devices_->actuators)
    if (a.index == *index) return a.adapter.get();
  colony::Actuator* device = table.actuators[*index];
  std::unique_ptr<CCI_Actuator> adapter;
  if (auto* wheels = dynamic_cast<colony::DifferentialSteering*>(device)) {
    adapter = std::make_unique<WheelsAdapter>(*wheels);
  } else if (auto* leds = dynamic_cast<colony::Leds*>(device)) {
    adapter = std::make_unique<LedsAdapter>(*leds);
  } else if (auto* rab = dynamic_cast<colony::RangeAndBearingActuator*>(device)) {
    adapter = std::make_unique<RangeAndBearingActuatorAdapter>(*rab);
  } else {
    THROW_ARGOSEXCEPTION("Actuator " << label
                                     << " has no ARGoS control interface in Colony's "
                                        "compatibility layer; provided: "
                                     << kProvidedActuators);
  }
  CCI_Actuator* result = adapter.get();
  devices_->actuators.push_back({*index, std::move(adapter)});
  return result;
}

}  // namespace internal
}  // namespace argos

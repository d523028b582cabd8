// Colours, byte arrays and the printing of sensor readings.
#include <cctype>
#include <sstream>

#include "argos3/core/utility/configuration/argos_exception.h"
#include "argos3/core/utility/datatypes/byte_array.h"
#include "argos3/core/utility/datatypes/color.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_base_ground_sensor.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_light_sensor.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_motor_ground_sensor.h"
#include "argos3/plugins/robots/foot-bot/control_interface/ci_footbot_proximity_sensor.h"

namespace argos {

namespace {

struct NamedColor {
  const char* name;
  const CColor* color;
};
const NamedColor kNamedColors[] = {
    {"black", &CColor::BLACK},   {"white", &CColor::WHITE},   {"red", &CColor::RED},
    {"green", &CColor::GREEN},   {"blue", &CColor::BLUE},     {"magenta", &CColor::MAGENTA},
    {"cyan", &CColor::CYAN},     {"yellow", &CColor::YELLOW}, {"orange", &CColor::ORANGE},
    {"brown", &CColor::BROWN},   {"purple", &CColor::PURPLE}, {"gray10", &CColor::GRAY10},
    {"gray20", &CColor::GRAY20}, {"gray30", &CColor::GRAY30}, {"gray40", &CColor::GRAY40},
    {"gray50", &CColor::GRAY50}, {"gray60", &CColor::GRAY60}, {"gray70", &CColor::GRAY70},
    {"gray80", &CColor::GRAY80}, {"gray90", &CColor::GRAY90},
};

// "r,g,b[,a]" with components 0..255.
bool ParseComponents(const std::string& text, CColor& out) {
  int values[4] = {0, 0, 0, 255};
  int count = 0;
  std::istringstream in(text);
  while (count < 4) {
    if (!(in >> values[count]) || values[count] < 0 || values[count] > 255) return false;
    ++count;
    if ((in >> std::ws).eof()) break;
    if (in.get() != ',') return false;
  }
  if (count < 3 || !(in >> std::ws).eof()) return false;
  out = CColor(static_cast<UInt8>(values[0]), static_cast<UInt8>(values[1]),
               static_cast<UInt8>(values[2]), static_cast<UInt8>(values[3]));
  return true;
}

template <typename Readings>
std::ostream& PrintValues(std::ostream& os, const Readings& readings) {
  for (size_t i = 0; i < readings.size(); ++i)
    os << (i ? " { " : "{ ") << readings[i].Value << " }";
  return os;
}

}  // namespace

void CColor::Set(const std::string& text) {
  for (const auto& named : kNamedColors) {
    if (text == named.name) {
      *this = *named.color;
      return;
    }
  }
  if (!ParseComponents(text, *this)) {
    THROW_ARGOSEXCEPTION("Unknown color \"" << text
                                            << "\"; accepted: black, white, red, green, blue, "
                                               "magenta, cyan, yellow, orange, brown, purple, "
                                               "gray10..gray90, or \"r,g,b[,a]\" with 0..255");
  }
}

std::ostream& operator<<(std::ostream& os, const CColor& color) {
  for (const auto& named : kNamedColors)
    if (color == *named.color) return os << named.name;
  return os << static_cast<unsigned>(color.red_) << "," << static_cast<unsigned>(color.green_)
            << "," << static_cast<unsigned>(color.blue_) << ","
            << static_cast<unsigned>(color.alpha_);
}

std::istream& operator>>(std::istream& is, CColor& color) {
  std::string text;
  if (!(is >> text)) return is;
  try {
    color.Set(text);
  } catch (const CARGoSException&) {
    is.setstate(std::ios::failbit);
  }
  return is;
}

void CByteArray::CheckAvailable(size_t size) const {
  if (bytes_.size() < size) {
    THROW_ARGOSEXCEPTION("CByteArray: cannot take " << size << " bytes from the front, only "
                                                    << bytes_.size() << " left");
  }
}

CByteArray& CByteArray::FetchBuffer(UInt8* buffer, size_t size) {
  CheckAvailable(size);
  std::copy(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(size), buffer);
  bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(size));
  return *this;
}

CByteArray& CByteArray::operator<<(const std::string& value) {
  bytes_.insert(bytes_.end(), value.begin(), value.end());
  bytes_.push_back(0);
  return *this;
}

CByteArray& CByteArray::operator>>(std::string& value) {
  const auto zero = std::find(bytes_.begin(), bytes_.end(), UInt8{0});
  if (zero == bytes_.end()) {
    THROW_ARGOSEXCEPTION("CByteArray: no string to take from the front (no terminating zero byte)");
  }
  value.assign(bytes_.begin(), zero);
  bytes_.erase(bytes_.begin(), zero + 1);
  return *this;
}

std::ostream& operator<<(std::ostream& os, const CByteArray& array) {
  os << "[";
  for (size_t i = 0; i < array.Size(); ++i) os << " " << static_cast<unsigned>(array[i]);
  return os << " ]";
}

std::ostream& operator<<(std::ostream& os, const CCI_FootBotProximitySensor::SReading& r) {
  return os << "Value=<" << r.Value << ">, Angle=<" << r.Angle << ">";
}
std::ostream& operator<<(std::ostream& os, const CCI_FootBotProximitySensor::TReadings& r) {
  return PrintValues(os, r);
}
std::ostream& operator<<(std::ostream& os, const CCI_FootBotLightSensor::SReading& r) {
  return os << "Value=<" << r.Value << ">, Angle=<" << r.Angle << ">";
}
std::ostream& operator<<(std::ostream& os, const CCI_FootBotLightSensor::TReadings& r) {
  return PrintValues(os, r);
}
std::ostream& operator<<(std::ostream& os, const CCI_FootBotMotorGroundSensor::SReading& r) {
  return os << "Value=<" << r.Value << ">, Offset=<" << r.Offset << ">";
}
std::ostream& operator<<(std::ostream& os, const CCI_FootBotMotorGroundSensor::TReadings& r) {
  return PrintValues(os, r);
}
std::ostream& operator<<(std::ostream& os, const CCI_FootBotBaseGroundSensor::SReading& r) {
  return os << "Value=<" << r.Value << ">, Offset=<" << r.Offset << ">";
}
std::ostream& operator<<(std::ostream& os, const CCI_FootBotBaseGroundSensor::TReadings& r) {
  return PrintValues(os, r);
}

}  // namespace argos

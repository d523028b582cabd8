// ARGoS compatibility layer (Colony): the configuration tree a controller's
// (or loop functions') Init receives, and ARGoS's functions to read it.
//
// In ARGoS the tree is the XML itself; in Colony it is built from the
// parameters the experiment file gives: a controller's tree is its <params>
// element, each attribute an attribute of the root; a parameter named with
// dots, "wheel_turning.max_speed", is the attribute max_speed of the child
// node wheel_turning. (This is how Colony passes the child elements of
// <params> that ARGoS files use: <params><wheel_turning max_speed="10"/>
// </params>.) Nodes have no text.
//
// Reading works as in ARGoS: GetNodeAttribute throws CARGoSException when
// the attribute is missing or malformed, GetNodeAttributeOrDefault gives the
// default only when it is missing (a malformed value still throws). Colony
// names the file, line and attribute of such an error. Values are read with
// the type's `>>` (numbers, CDegrees, CRadians, CRange "min:max", CVector2
// "x,y", CVector3 "x,y,z", CColor names or "r,g,b[,a]", CQuaternion "z,y,x"
// degrees), strings whole, bool as true/false; integers must be whole and fit
// the type (a negative count is an error, not a huge one). An attribute the
// controller never reads gets one warning per controller.
#pragma once

#include <cerrno>
#include <cstdlib>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <typeinfo>

#include "argos3/core/utility/configuration/argos_exception.h"
#include "argos3/core/utility/datatypes/color.h"
#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/angles.h"
#include "argos3/core/utility/math/quaternion.h"
#include "argos3/core/utility/math/range.h"
#include "argos3/core/utility/math/vector2.h"
#include "argos3/core/utility/math/vector3.h"

namespace argos {

// A node of the configuration tree. Copies share the node (as ARGoS's XML
// elements do). The tree handed to Init lives until Init returns; a copy
// (TConfigurationNode by value, not a reference) keeps its node alive longer.
class TConfigurationNode {
 public:
  struct Data;
  // A node with no name, attributes or children.
  TConfigurationNode();
  explicit TConfigurationNode(std::shared_ptr<Data> data) : data_(std::move(data)) {}

  // The node's element name ("params", "wheel_turning").
  const std::string& Value() const;

  // For the functions below and the host.
  Data& data() const { return *data_; }

 private:
  std::shared_ptr<Data> data_;
};

// Iterates over a node's children, all of them or those named `tag`:
//   TConfigurationNodeIterator it("item");
//   for (it = it.begin(&node); it != it.end(); ++it) GetNodeAttribute(*it, "x", x);
class TConfigurationNodeIterator {
 public:
  explicit TConfigurationNodeIterator(const std::string& tag = "") : tag_(tag) {}
  TConfigurationNodeIterator begin(TConfigurationNode* parent) const;
  TConfigurationNodeIterator end() const { return TConfigurationNodeIterator(tag_); }
  TConfigurationNodeIterator& operator++();
  bool operator==(const TConfigurationNodeIterator& other) const { return node_ == other.node_; }
  bool operator!=(const TConfigurationNodeIterator& other) const { return node_ != other.node_; }
  TConfigurationNode& operator*() const { return *node_; }
  TConfigurationNode* operator->() const { return node_; }

 private:
  void Seek(size_t from);

  std::string tag_;
  TConfigurationNode* parent_ = nullptr;
  TConfigurationNode* node_ = nullptr;
  size_t index_ = 0;
};

namespace internal {

// The text of attribute `name` of `node`, marked as read; nullptr when absent.
const std::string* FindAttribute(TConfigurationNode& node, const std::string& name);
// Throws the CARGoSException of a missing attribute.
[[noreturn]] void ThrowMissingAttribute(TConfigurationNode& node, const std::string& name);
// Throws the CARGoSException of a malformed attribute, saying what is accepted.
[[noreturn]] void ThrowMalformedAttribute(TConfigurationNode& node, const std::string& name,
                                          const std::string& text, const std::string& accepted);
std::string TypeName(const std::type_info& type);

// What a value of type T is written as, for error messages.
template <typename T>
std::string Accepted() {
  if constexpr (std::is_same_v<T, bool>) {
    return "true or false";
  } else if constexpr (std::is_integral_v<T>) {
    std::ostringstream s;
    s << "a whole number in [" << +std::numeric_limits<T>::min() << ", "
      << +std::numeric_limits<T>::max() << "]";
    return s.str();
  } else if constexpr (std::is_floating_point_v<T>) {
    return "a finite number";
  } else if constexpr (std::is_same_v<T, CDegrees>) {
    return "a number (degrees)";
  } else if constexpr (std::is_same_v<T, CRadians>) {
    return "a number (radians)";
  } else if constexpr (std::is_same_v<T, CVector2>) {
    return "\"x,y\"";
  } else if constexpr (std::is_same_v<T, CVector3>) {
    return "\"x,y,z\"";
  } else if constexpr (std::is_same_v<T, CQuaternion>) {
    return "\"z,y,x\" (angles in degrees)";
  } else if constexpr (std::is_same_v<T, CColor>) {
    return "a colour name (black, white, red, green, blue, magenta, cyan, yellow, orange, brown, "
           "purple, gray10..gray90) or \"r,g,b[,a]\" with components 0..255";
  } else {
    return "a value of type " + TypeName(typeid(T));
  }
}

template <typename T>
struct IsRange : std::false_type {};
template <typename U>
struct IsRange<CRange<U>> : std::true_type {
  using Element = U;
};

// Reads `text` into `out`; false when it is malformed (then `out` is unchanged).
template <typename T>
bool Parse(const std::string& text, T& out) {
  if constexpr (std::is_same_v<T, std::string>) {
    out = text;
    return true;
  } else if constexpr (std::is_same_v<T, bool>) {
    if (text != "true" && text != "false") return false;
    out = text == "true";
    return true;
  } else if constexpr (std::is_integral_v<T>) {
    const char* begin = text.c_str();
    char* end = nullptr;
    errno = 0;
    if constexpr (std::is_signed_v<T>) {
      const long long v = std::strtoll(begin, &end, 10);
      if (end == begin || errno == ERANGE || v < std::numeric_limits<T>::min() ||
          v > std::numeric_limits<T>::max())
        return false;
      while (*end == ' ') ++end;
      if (*end != '\0') return false;
      out = static_cast<T>(v);
    } else {
      size_t first = text.find_first_not_of(' ');
      if (first == std::string::npos || text[first] == '-') return false;
      const unsigned long long v = std::strtoull(begin, &end, 10);
      if (end == begin || errno == ERANGE || v > std::numeric_limits<T>::max()) return false;
      while (*end == ' ') ++end;
      if (*end != '\0') return false;
      out = static_cast<T>(v);
    }
    return true;
  } else if constexpr (std::is_floating_point_v<T>) {
    const char* begin = text.c_str();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(begin, &end);
    if (end == begin || errno == ERANGE || !std::isfinite(v)) return false;
    while (*end == ' ') ++end;
    if (*end != '\0') return false;
    out = static_cast<T>(v);
    return true;
  } else {
    std::istringstream in(text);
    T value{};
    if (!(in >> value) || !(in >> std::ws).eof()) return false;
    out = value;
    return true;
  }
}

template <typename T>
std::string AcceptedText() {
  if constexpr (IsRange<T>::value) {
    return "\"min:max\", each " + Accepted<typename IsRange<T>::Element>();
  } else {
    return Accepted<T>();
  }
}

}  // namespace internal

// Whether `node` has a child named `tag`.
bool NodeExists(TConfigurationNode& node, const std::string& tag) noexcept;
// The first child of `node` named `tag`; throws CARGoSException when none.
TConfigurationNode& GetNode(TConfigurationNode& node, const std::string& tag);
// Whether `node` has attribute `name` (it then counts as read).
bool NodeAttributeExists(TConfigurationNode& node, const std::string& name);

template <typename T>
void GetNodeAttribute(TConfigurationNode& node, const std::string& name, T& buffer) {
  const std::string* text = internal::FindAttribute(node, name);
  if (text == nullptr) internal::ThrowMissingAttribute(node, name);
  if (!internal::Parse(*text, buffer))
    internal::ThrowMalformedAttribute(node, name, *text, internal::AcceptedText<T>());
}

template <typename T>
void GetNodeAttributeOrDefault(TConfigurationNode& node, const std::string& name, T& buffer,
                               const T& default_value) {
  const std::string* text = internal::FindAttribute(node, name);
  if (text == nullptr) {
    buffer = default_value;
    return;
  }
  if (!internal::Parse(*text, buffer))
    internal::ThrowMalformedAttribute(node, name, *text, internal::AcceptedText<T>());
}

}  // namespace argos

// Reading experiment files. A ConfigNode wraps one XML element and reads
// typed attributes from it; every problem is recorded (file, line, element,
// attribute, value, what is accepted) in the file's Diagnostics instead of
// being thrown at once, so a read reports all problems together.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/color.h"
#include "core/control_interface.h"
#include "core/error.h"
#include "core/text.h"

namespace tinyxml2 {
class XMLElement;
}

namespace colony {

// The file being read and the problems found in it so far.
struct ConfigContext {
  std::string file;
  Diagnostics diagnostics;
};

struct Range {
  double min = -std::numeric_limits<double>::max();
  double max = std::numeric_limits<double>::max();
  bool min_exclusive = false;
  std::string Describe() const;
  static Range Positive() { return {0.0, std::numeric_limits<double>::max(), true}; }
  static Range NonNegative() { return {0.0, std::numeric_limits<double>::max(), false}; }
  static Range Between(double a, double b) { return {a, b, false}; }
};

class ConfigNode {
 public:
  ConfigNode() = default;
  ConfigNode(const tinyxml2::XMLElement* element, ConfigContext* context)
      : element_(element), context_(context) {}

  bool valid() const { return element_ != nullptr; }
  std::string name() const;
  int line() const;
  const std::string& file() const { return context_->file; }
  ConfigContext& context() const { return *context_; }
  const tinyxml2::XMLElement* element() const { return element_; }
  // "box id="b1"": the element as a message names it.
  std::string Label() const;

  bool Has(std::string_view attribute) const;
  std::vector<std::string> AttributeNames() const;

  // Typed getters. On a missing attribute they return the fallback; on a bad
  // value they record a diagnostic and return the fallback.
  std::string GetString(std::string_view attribute, std::string_view fallback) const;
  std::string RequireString(std::string_view attribute) const;
  double GetDouble(std::string_view attribute, double fallback, const Range& range = {}) const;
  double RequireDouble(std::string_view attribute, const Range& range = {}) const;
  int64_t GetInt(std::string_view attribute, int64_t fallback, int64_t min = 0,
                 int64_t max = std::numeric_limits<int64_t>::max()) const;
  int64_t RequireInt(std::string_view attribute, int64_t min = 0,
                     int64_t max = std::numeric_limits<int64_t>::max()) const;
  bool GetBool(std::string_view attribute, bool fallback) const;
  // `count` comma-separated finite numbers ("x,y,z").
  std::array<double, 3> GetTriple(std::string_view attribute, std::array<double, 3> fallback,
                                  const Range& range = {}) const;
  std::array<double, 3> RequireTriple(std::string_view attribute, const Range& range = {}) const;
  // Two comma-separated finite numbers ("x,y").
  std::array<double, 2> GetPair(std::string_view attribute, std::array<double, 2> fallback,
                                const Range& range = {}) const;
  std::array<double, 2> RequirePair(std::string_view attribute, const Range& range = {}) const;
  std::string GetChoice(std::string_view attribute, const std::vector<std::string>& choices,
                        std::string_view fallback) const;
  Color GetColor(std::string_view attribute, Color fallback) const;

  std::vector<ConfigNode> Children() const;
  std::vector<ConfigNode> Children(std::string_view name) const;
  ConfigNode Child(std::string_view name) const;  // the first one, or an invalid node

  // Reports every attribute not in `allowed`, with a "did you mean".
  void CheckAttributes(const std::vector<std::string>& allowed) const;
  // Reports every child element not in `allowed`, with a "did you mean".
  void CheckChildren(const std::vector<std::string>& allowed) const;
  // Reports a second occurrence of any child named `name`.
  void CheckAtMostOne(std::string_view name) const;

  void Error(std::string_view attribute, std::string_view value, const std::string& message) const;
  void ElementError(const std::string& message) const;

  // All attributes as controller parameters.
  Params ToParams() const;

 private:
  const char* Raw(std::string_view attribute) const;
  const tinyxml2::XMLElement* element_ = nullptr;
  ConfigContext* context_ = nullptr;
};

// A finite number, or false.
bool ParseFiniteDouble(std::string_view text, double& out);

}  // namespace colony

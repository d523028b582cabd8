#include "core/config.h"

#include <tinyxml2.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace colony {

namespace {

// "a whole number in [0, 256]", or "a whole number >= 0" when unbounded above.
std::string DescribeWholeRange(int64_t min, int64_t max) {
  if (max == std::numeric_limits<int64_t>::max()) return "a whole number >= " + std::to_string(min);
  return "a whole number in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
}

}  // namespace

std::string Range::Describe() const {
  const bool has_min = min > -std::numeric_limits<double>::max();
  const bool has_max = max < std::numeric_limits<double>::max();
  if (has_min && has_max) {
    return std::string("a number in ") + (min_exclusive ? "(" : "[") + FormatNumber(min) + ", " +
           FormatNumber(max) + "]";
  }
  if (has_min) return std::string("a number ") + (min_exclusive ? "> " : ">= ") + FormatNumber(min);
  if (has_max) return "a number <= " + FormatNumber(max);
  return "a finite number";
}

bool ParseFiniteDouble(std::string_view text, double& out) {
  std::string s(text);
  const char* begin = s.c_str();
  while (*begin == ' ') ++begin;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin) return false;
  while (*end == ' ') ++end;
  if (*end != '\0' || errno == ERANGE || !std::isfinite(v)) return false;
  out = v;
  return true;
}

std::string ConfigNode::name() const { return element_ ? element_->Name() : ""; }
int ConfigNode::line() const { return element_ ? element_->GetLineNum() : 0; }

std::string ConfigNode::Label() const {
  std::string label = name();
  if (const char* id = element_ ? element_->Attribute("id") : nullptr) {
    label += " id=\"" + std::string(id) + "\"";
  }
  return label;
}

const char* ConfigNode::Raw(std::string_view attribute) const {
  return element_ ? element_->Attribute(std::string(attribute).c_str()) : nullptr;
}

bool ConfigNode::Has(std::string_view attribute) const { return Raw(attribute) != nullptr; }

std::vector<std::string> ConfigNode::AttributeNames() const {
  std::vector<std::string> names;
  for (auto* a = element_->FirstAttribute(); a; a = a->Next()) names.emplace_back(a->Name());
  return names;
}

void ConfigNode::Error(std::string_view attribute, std::string_view value,
                       const std::string& message) const {
  context_->diagnostics.Add(Diagnostic{context_->file, line(), Label(), std::string(attribute),
                                       std::string(value), message});
}

void ConfigNode::ElementError(const std::string& message) const {
  context_->diagnostics.Add(Diagnostic{context_->file, line(), Label(), "", "", message});
}

std::string ConfigNode::GetString(std::string_view attribute, std::string_view fallback) const {
  const char* raw = Raw(attribute);
  return raw ? std::string(raw) : std::string(fallback);
}

std::string ConfigNode::RequireString(std::string_view attribute) const {
  const char* raw = Raw(attribute);
  if (!raw) {
    Error(attribute, "", "required attribute is missing");
    return "";
  }
  if (*raw == '\0') Error(attribute, raw, "must not be empty");
  return raw;
}

static bool CheckRange(const ConfigNode& node, std::string_view attribute, std::string_view raw,
                       double v, const Range& range) {
  const bool below = range.min_exclusive ? v <= range.min : v < range.min;
  if (below || v > range.max) {
    node.Error(attribute, raw,
               "'" + std::string(raw) + "' is out of range; accepted: " + range.Describe());
    return false;
  }
  return true;
}

double ConfigNode::GetDouble(std::string_view attribute, double fallback,
                             const Range& range) const {
  const char* raw = Raw(attribute);
  if (!raw) return fallback;
  double v = 0;
  if (!ParseFiniteDouble(raw, v)) {
    Error(attribute, raw,
          "'" + std::string(raw) + "' is not a finite number; accepted: " + range.Describe());
    return fallback;
  }
  return CheckRange(*this, attribute, raw, v, range) ? v : fallback;
}

double ConfigNode::RequireDouble(std::string_view attribute, const Range& range) const {
  if (!Has(attribute)) {
    Error(attribute, "", "required attribute is missing; accepted: " + range.Describe());
    return 0;
  }
  return GetDouble(attribute, 0, range);
}

int64_t ConfigNode::GetInt(std::string_view attribute, int64_t fallback, int64_t min,
                           int64_t max) const {
  const char* raw = Raw(attribute);
  if (!raw) return fallback;
  const std::string accepted = DescribeWholeRange(min, max);
  const char* begin = raw;
  while (*begin == ' ') ++begin;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(begin, &end, 10);
  while (end != begin && *end == ' ') ++end;
  if (*begin == '\0' || end == begin || *end != '\0' || errno == ERANGE) {
    Error(attribute, raw,
          "'" + std::string(raw) + "' is not a whole number; accepted: " + accepted);
    return fallback;
  }
  if (v < min || v > max) {
    Error(attribute, raw, "'" + std::string(raw) + "' is out of range; accepted: " + accepted);
    return fallback;
  }
  return v;
}

int64_t ConfigNode::RequireInt(std::string_view attribute, int64_t min, int64_t max) const {
  if (!Has(attribute)) {
    Error(attribute, "",
          "required attribute is missing; accepted: " + DescribeWholeRange(min, max));
    return min;
  }
  return GetInt(attribute, min, min, max);
}

bool ConfigNode::GetBool(std::string_view attribute, bool fallback) const {
  const char* raw = Raw(attribute);
  if (!raw) return fallback;
  const std::string v(raw);
  if (v == "true") return true;
  if (v == "false") return false;
  Error(attribute, raw, "'" + v + "' is not a boolean; accepted: true, false");
  return fallback;
}

std::array<double, 3> ConfigNode::GetTriple(std::string_view attribute,
                                            std::array<double, 3> fallback,
                                            const Range& range) const {
  const char* raw = Raw(attribute);
  if (!raw) return fallback;
  const auto parts = SplitList(raw);
  std::array<double, 3> out{};
  bool ok = parts.size() == 3;
  for (size_t i = 0; ok && i < 3; ++i) ok = ParseFiniteDouble(parts[i], out[i]);
  if (!ok) {
    Error(attribute, raw,
          "'" + std::string(raw) + "' is not three finite numbers; accepted: \"x,y,z\"");
    return fallback;
  }
  for (double v : out) {
    if (!CheckRange(*this, attribute, raw, v, range)) return fallback;
  }
  return out;
}

std::array<double, 3> ConfigNode::RequireTriple(std::string_view attribute,
                                                const Range& range) const {
  if (!Has(attribute)) {
    Error(attribute, "", "required attribute is missing; accepted: \"x,y,z\"");
    return {0, 0, 0};
  }
  return GetTriple(attribute, {0, 0, 0}, range);
}

std::array<double, 2> ConfigNode::GetPair(std::string_view attribute,
                                          std::array<double, 2> fallback,
                                          const Range& range) const {
  const char* raw = Raw(attribute);
  if (!raw) return fallback;
  const auto parts = SplitList(raw);
  std::array<double, 2> out{};
  bool ok = parts.size() == 2;
  for (size_t i = 0; ok && i < 2; ++i) ok = ParseFiniteDouble(parts[i], out[i]);
  if (!ok) {
    Error(attribute, raw,
          "'" + std::string(raw) + "' is not two finite numbers; accepted: \"x,y\"");
    return fallback;
  }
  for (double v : out) {
    if (!CheckRange(*this, attribute, raw, v, range)) return fallback;
  }
  return out;
}

std::array<double, 2> ConfigNode::RequirePair(std::string_view attribute,
                                              const Range& range) const {
  if (!Has(attribute)) {
    Error(attribute, "", "required attribute is missing; accepted: \"x,y\"");
    return {0, 0};
  }
  return GetPair(attribute, {0, 0}, range);
}

std::string ConfigNode::GetChoice(std::string_view attribute,
                                  const std::vector<std::string>& choices,
                                  std::string_view fallback) const {
  const char* raw = Raw(attribute);
  if (!raw) return std::string(fallback);
  for (const auto& c : choices) {
    if (c == raw) return c;
  }
  std::string message = "'" + std::string(raw) + "' is not accepted; accepted: " + Join(choices);
  const std::string guess = DidYouMean(raw, choices);
  if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
  Error(attribute, raw, message);
  return std::string(fallback);
}

Color ConfigNode::GetColor(std::string_view attribute, Color fallback) const {
  const char* raw = Raw(attribute);
  if (!raw) return fallback;
  if (auto c = ParseColor(raw)) return *c;
  Error(attribute, raw, "'" + std::string(raw) + "' is not a colour; accepted: " + kColorAccepted);
  return fallback;
}

std::vector<ConfigNode> ConfigNode::Children() const {
  std::vector<ConfigNode> out;
  if (!element_) return out;
  for (auto* c = element_->FirstChildElement(); c; c = c->NextSiblingElement()) {
    out.emplace_back(c, context_);
  }
  return out;
}

std::vector<ConfigNode> ConfigNode::Children(std::string_view name) const {
  std::vector<ConfigNode> out;
  if (!element_) return out;
  const std::string n(name);
  for (auto* c = element_->FirstChildElement(n.c_str()); c; c = c->NextSiblingElement(n.c_str())) {
    out.emplace_back(c, context_);
  }
  return out;
}

ConfigNode ConfigNode::Child(std::string_view name) const {
  if (!element_) return {};
  return ConfigNode(element_->FirstChildElement(std::string(name).c_str()), context_);
}

void ConfigNode::CheckAttributes(const std::vector<std::string>& allowed) const {
  for (auto* a = element_->FirstAttribute(); a; a = a->Next()) {
    bool ok = false;
    for (const auto& name : allowed) ok = ok || name == a->Name();
    if (ok) continue;
    std::string message = "unknown attribute";
    const std::string guess = DidYouMean(a->Name(), allowed);
    if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
    message +=
        allowed.empty() ? "; this element takes no attributes" : "; accepted: " + Join(allowed);
    Error(a->Name(), a->Value(), message);
  }
}

void ConfigNode::CheckChildren(const std::vector<std::string>& allowed) const {
  for (const auto& child : Children()) {
    const std::string n = child.name();
    bool ok = false;
    for (const auto& name : allowed) ok = ok || name == n;
    if (ok) continue;
    std::string message = "unknown element inside <" + name() + ">";
    const std::string guess = DidYouMean(n, allowed);
    if (!guess.empty()) message += " (did you mean <" + guess + ">?)";
    message += allowed.empty() ? "; it takes no child elements" : "; accepted: " + Join(allowed);
    child.ElementError(message);
  }
}

void ConfigNode::CheckAtMostOne(std::string_view name) const {
  const auto items = Children(name);
  for (size_t i = 1; i < items.size(); ++i) {
    items[i].ElementError("<" + std::string(name) + "> given more than once inside <" +
                          this->name() + "> (first at line " + std::to_string(items[0].line()) +
                          ")");
  }
}

Params ConfigNode::ToParams() const {
  Params params;
  if (!element_) return params;
  params.SetBaseDirectory(std::filesystem::path(file()).parent_path().string());
  for (auto* a = element_->FirstAttribute(); a; a = a->Next()) params.Set(a->Name(), a->Value());
  return params;
}

}  // namespace colony

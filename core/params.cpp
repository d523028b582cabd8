#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "core/control_interface.h"

namespace colony {

void Params::Set(std::string key, std::string value) {
  for (auto& e : entries_) {
    if (e.key == key) {
      e.value = std::move(value);
      e.number.reset();
      return;
    }
  }
  entries_.push_back({std::move(key), std::move(value)});
}

const Params::Entry* Params::Find(std::string_view key) const {
  bool known = false;
  for (const auto& k : asked_) known = known || k == key;
  if (!known) asked_.emplace_back(key);
  for (const auto& e : entries_) {
    if (e.key == key) {
      e.read = true;
      return &e;
    }
  }
  return nullptr;
}

template <class Text>
void Params::NoteDefault(std::string_view key, Default::Kind kind, Text&& text) const {
  for (const auto& d : defaults_)
    if (d.key == key) return;
  defaults_.push_back({std::string(key), std::string(text()), kind});
}

// Shortest text that reads back as `v`.
static std::string NumberText(double v) {
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, v).ptr);
}

bool Params::Has(std::string_view key) const { return Find(key) != nullptr; }

std::string Params::GetString(std::string_view key, std::string_view fallback) const {
  NoteDefault(key, Default::kText, [&] { return fallback; });
  const Entry* e = Find(key);
  return e ? e->value : std::string(fallback);
}

std::string Params::GetString(std::string_view key) const {
  NoteDefault(key, Default::kRequired, [] { return ""; });
  const Entry* e = Find(key);
  if (!e)
    throw ParamError(std::string(key), "",
                     "required parameter '" + std::string(key) + "' is missing");
  return e->value;
}

static double ParseDouble(const std::string& key, const std::string& text, double min, double max) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  while (end && *end == ' ') ++end;
  if (text.empty() || end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
    throw ParamError(key, text, "parameter '" + key + "': '" + text + "' is not a finite number");
  }
  if (v < min || v > max) {
    throw ParamError(key, text,
                     "parameter '" + key + "': " + text + " is out of range; accepted: [" +
                         std::to_string(min) + ", " + std::to_string(max) + "]");
  }
  return v;
}

double Params::GetDouble(std::string_view key, double fallback, double min, double max) const {
  NoteDefault(key, Default::kNumber, [&] { return NumberText(fallback); });
  const Entry* e = Find(key);
  if (!e) return fallback;
  // Every robot of a controller reads the same parameters: the text is
  // parsed by the first, and the number checked against each caller's range.
  if (!e->number) e->number = ParseDouble(e->key, e->value, min, max);
  return *e->number >= min && *e->number <= max ? *e->number
                                                : ParseDouble(e->key, e->value, min, max);
}

double Params::GetDouble(std::string_view key) const {
  NoteDefault(key, Default::kRequired, [] { return ""; });
  return ParseDouble(std::string(key), GetString(key), -1e300, 1e300);
}

std::vector<double> Params::GetNumbers(std::string_view key, std::string_view fallback,
                                       size_t count, double min, double max) const {
  NoteDefault(key, Default::kText, [&] { return fallback; });
  const Entry* e = Find(key);
  const std::string name(key);
  const std::string text = e ? e->value : std::string(fallback);
  std::vector<double> out;
  size_t begin = 0;
  while (true) {
    const size_t comma = text.find(',', begin);
    std::string part = text.substr(begin, comma == std::string::npos ? comma : comma - begin);
    while (!part.empty() && part.front() == ' ') part.erase(part.begin());
    out.push_back(ParseDouble(name, part, min, max));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  if (count > 0 && out.size() != count) {
    throw ParamError(name, text,
                     "parameter '" + name + "': '" + text + "' has " + std::to_string(out.size()) +
                         " numbers; accepted: " + std::to_string(count) +
                         " numbers separated by commas");
  }
  return out;
}

int64_t Params::GetInt(std::string_view key, int64_t fallback, int64_t min, int64_t max) const {
  NoteDefault(key, Default::kNumber, [&] { return std::to_string(fallback); });
  const Entry* e = Find(key);
  if (!e) return fallback;
  const char* begin = e->value.c_str();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(begin, &end, 10);
  if (e->value.empty() || *end != '\0' || errno == ERANGE) {
    throw ParamError(e->key, e->value,
                     "parameter '" + e->key + "': '" + e->value + "' is not a whole number");
  }
  if (v < min || v > max) {
    throw ParamError(e->key, e->value,
                     "parameter '" + e->key + "': " + e->value + " is out of range; accepted: [" +
                         std::to_string(min) + ", " + std::to_string(max) + "]");
  }
  return v;
}

bool Params::GetBool(std::string_view key, bool fallback) const {
  NoteDefault(key, Default::kText, [&] { return fallback ? "true" : "false"; });
  const Entry* e = Find(key);
  if (!e) return fallback;
  if (e->value == "true" || e->value == "1") return true;
  if (e->value == "false" || e->value == "0") return false;
  throw ParamError(
      e->key, e->value,
      "parameter '" + e->key + "': '" + e->value + "' is not a boolean; accepted: true, false");
}

std::vector<std::string> Params::Unread() const {
  std::vector<std::string> out;
  for (const auto& e : entries_)
    if (!e.read) out.push_back(e.key);
  return out;
}

}  // namespace colony

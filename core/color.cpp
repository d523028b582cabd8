#include "core/color.h"

#include <cstdlib>

#include "core/config.h"

namespace colony {

std::optional<Color> ParseColor(std::string_view text) {
  struct Named {
    const char* name;
    Color color;
  };
  static const Named kNamed[] = {
      {"black", {0, 0, 0, 255}},       {"white", {255, 255, 255, 255}},
      {"red", {255, 0, 0, 255}},       {"green", {0, 255, 0, 255}},
      {"blue", {0, 0, 255, 255}},      {"yellow", {255, 255, 0, 255}},
      {"magenta", {255, 0, 255, 255}}, {"cyan", {0, 255, 255, 255}},
      {"orange", {255, 140, 0, 255}},  {"brown", {165, 42, 42, 255}},
      {"purple", {160, 32, 240, 255}}, {"off", {0, 0, 0, 255}},
  };
  for (const auto& n : kNamed) {
    if (text == n.name) return n.color;
  }
  for (std::string_view prefix : {"gray", "grey"}) {
    if (text.size() == 6 && text.substr(0, 4) == prefix && text[5] == '0' && text[4] >= '1' &&
        text[4] <= '9') {
      const uint8_t v = static_cast<uint8_t>((text[4] - '0') * 255 / 10);
      return Color{v, v, v, 255};
    }
  }
  const auto parts = SplitList(text);
  if (parts.size() != 3 && parts.size() != 4) return std::nullopt;
  uint8_t c[4] = {0, 0, 0, 255};
  for (size_t i = 0; i < parts.size(); ++i) {
    char* end = nullptr;
    const long v = std::strtol(parts[i].c_str(), &end, 10);
    if (parts[i].empty() || *end != '\0' || v < 0 || v > 255) return std::nullopt;
    c[i] = static_cast<uint8_t>(v);
  }
  return Color{c[0], c[1], c[2], c[3]};
}

}  // namespace colony

// An RGBA colour, 8 bits per channel: LEDs, bodies, the floor.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace colony {

struct Color {
  uint8_t r = 0, g = 0, b = 0, a = 255;
  friend bool operator==(const Color&, const Color&) = default;
  // Grey level in [0, 1] (luma), what a ground sensor reads.
  double Grey() const { return (0.299 * r + 0.587 * g + 0.114 * b) / 255.0; }
  static constexpr Color Black() { return {0, 0, 0, 255}; }
  static constexpr Color White() { return {255, 255, 255, 255}; }
};

// Parses a colour name (black, white, red, green, blue, yellow, magenta,
// cyan, orange, brown, purple, gray10..gray90 / grey10..grey90) or
// "r,g,b[,a]" with 0..255 components. Empty optional when malformed.
std::optional<Color> ParseColor(std::string_view text);
inline constexpr const char* kColorAccepted =
    "a colour name (black, white, red, green, blue, yellow, magenta, cyan, orange, brown, purple, "
    "gray10..gray90) or \"r,g,b[,a]\" with components 0..255";

}  // namespace colony

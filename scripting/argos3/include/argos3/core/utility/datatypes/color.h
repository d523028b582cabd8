// ARGoS compatibility layer (Colony): CColor, an RGBA colour with 8 bits per
// channel, and ARGoS's named colours (CColor::RED, CColor::GRAY50...).
#pragma once

#include <iostream>
#include <string>

#include "argos3/core/utility/datatypes/datatypes.h"

namespace argos {

class CColor {
 public:
  static const CColor BLACK;
  static const CColor WHITE;
  static const CColor RED;
  static const CColor GREEN;
  static const CColor BLUE;
  static const CColor MAGENTA;
  static const CColor CYAN;
  static const CColor YELLOW;
  static const CColor ORANGE;
  static const CColor BROWN;
  static const CColor PURPLE;
  static const CColor GRAY10;
  static const CColor GRAY20;
  static const CColor GRAY30;
  static const CColor GRAY40;
  static const CColor GRAY50;
  static const CColor GRAY60;
  static const CColor GRAY70;
  static const CColor GRAY80;
  static const CColor GRAY90;

  // Black, opaque.
  constexpr CColor() : red_(0), green_(0), blue_(0), alpha_(255) {}
  constexpr explicit CColor(UInt8 red, UInt8 green, UInt8 blue, UInt8 alpha = 255)
      : red_(red), green_(green), blue_(blue), alpha_(alpha) {}

  // Grey level in [0, 255] (luma: 0.299 R + 0.587 G + 0.114 B).
  Real ToGrayScale() const { return 0.299 * red_ + 0.587 * green_ + 0.114 * blue_; }
  UInt8 GetRed() const { return red_; }
  void SetRed(UInt8 value) { red_ = value; }
  UInt8 GetGreen() const { return green_; }
  void SetGreen(UInt8 value) { green_ = value; }
  UInt8 GetBlue() const { return blue_; }
  void SetBlue(UInt8 value) { blue_ = value; }
  UInt8 GetAlpha() const { return alpha_; }
  void SetAlpha(UInt8 value) { alpha_ = value; }
  void Set(UInt8 red, UInt8 green, UInt8 blue, UInt8 alpha = 255) {
    red_ = red;
    green_ = green;
    blue_ = blue;
    alpha_ = alpha;
  }
  // A colour name (black, white, red, green, blue, magenta, cyan, yellow,
  // orange, brown, purple, gray10..gray90) or "r,g,b[,a]" with 0..255
  // components. Throws CARGoSException on anything else.
  void Set(const std::string& text);
  // This colour over `background`, by this colour's alpha.
  CColor Blend(const CColor& background) const {
    const Real a = alpha_ / 255.0;
    auto mix = [a](UInt8 front, UInt8 back) {
      return static_cast<UInt8>(a * front + (1 - a) * back + 0.5);
    };
    return CColor(mix(red_, background.red_), mix(green_, background.green_),
                  mix(blue_, background.blue_), 255);
  }
  // 0xAARRGGBB.
  operator UInt32() const {
    return static_cast<UInt32>(alpha_) << 24 | static_cast<UInt32>(red_) << 16 |
           static_cast<UInt32>(green_) << 8 | blue_;
  }
  bool operator==(const CColor& o) const {
    return red_ == o.red_ && green_ == o.green_ && blue_ == o.blue_ && alpha_ == o.alpha_;
  }
  bool operator!=(const CColor& o) const { return !(*this == o); }

  // Writes the colour's name when it has one, "r,g,b,a" otherwise.
  friend std::ostream& operator<<(std::ostream& os, const CColor& color);
  // Reads what Set(text) accepts.
  friend std::istream& operator>>(std::istream& is, CColor& color);

 private:
  UInt8 red_, green_, blue_, alpha_;
};

inline const CColor CColor::BLACK{0, 0, 0};
inline const CColor CColor::WHITE{255, 255, 255};
inline const CColor CColor::RED{255, 0, 0};
inline const CColor CColor::GREEN{0, 255, 0};
inline const CColor CColor::BLUE{0, 0, 255};
inline const CColor CColor::MAGENTA{255, 0, 255};
inline const CColor CColor::CYAN{0, 255, 255};
inline const CColor CColor::YELLOW{255, 255, 0};
inline const CColor CColor::ORANGE{255, 140, 0};
inline const CColor CColor::BROWN{165, 42, 42};
inline const CColor CColor::PURPLE{160, 32, 240};
inline const CColor CColor::GRAY10{26, 26, 26};
inline const CColor CColor::GRAY20{51, 51, 51};
inline const CColor CColor::GRAY30{77, 77, 77};
inline const CColor CColor::GRAY40{102, 102, 102};
inline const CColor CColor::GRAY50{127, 127, 127};
inline const CColor CColor::GRAY60{153, 153, 153};
inline const CColor CColor::GRAY70{179, 179, 179};
inline const CColor CColor::GRAY80{204, 204, 204};
inline const CColor CColor::GRAY90{229, 229, 229};

}  // namespace argos

// What the Push-Pull robots (seed 003, chapter 6) say to each other and show:
// the range-and-bearing payload and the LED colours shared by
// pushpull_footbot and pushpull_handbot. Control-interface types only.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "actuators/range_and_bearing/range_and_bearing.h"
#include "core/color.h"

namespace colony::pushpull {

// Range-and-bearing payload (at least kPayloadSize bytes):
//   byte 0: the message (Message), byte 1: the sender (Sender),
//   bytes 2-3: the sender's token (a foot-bot's random priority while it
//   connects, big-endian).
inline constexpr int kPayloadSize = 4;
// Refuses an emitter whose payload cannot hold a message.
inline void CheckPayload(const RangeAndBearingActuator& emitter, const std::string& controller) {
  if (emitter.size() >= static_cast<size_t>(kPayloadSize)) return;
  throw std::runtime_error("the range_and_bearing actuator's payload holds " +
                           std::to_string(emitter.size()) + " byte(s); " + controller + " sends " +
                           std::to_string(kPayloadSize) +
                           " (give the actuator data_size=\"4\" or more)");
}
enum Message : uint8_t {
  kNothing = 0,
  kPause = 1,    // a foot-bot connecting to a hand-bot: active foot-bots nearby hold still
  kWait = 2,     // a hand-bot lifting or going down: foot-bots nearby hold still
  kTryLift = 3,  // a hand-bot asks every hand-bot that hears it to try to lift
};
enum Sender : uint8_t { kFootBot = 1, kHandBot = 2 };

// A slot is two adjacent LEDs of a hand-bot's ring: blue, and counter-
// clockwise from it (seen from above) green (pull) or violet (push).
inline constexpr Color kSlotBlue{0, 0, 255, 255};
inline constexpr Color kPullGreen{0, 255, 0, 255};
inline constexpr Color kPushViolet{160, 0, 255, 255};
// A foot-bot connecting, pushing or pulling lights all its LEDs yellow.
inline constexpr Color kBusyYellow{255, 255, 0, 255};
inline constexpr Color kOff{0, 0, 0, 255};

enum class Colour { kOther, kBlue, kGreen, kViolet, kYellow };
// What a camera blob of colour (r, g, b) shows.
inline Colour Classify(uint8_t r, uint8_t g, uint8_t b) {
  if (b > 180 && g < 80 && r < 80) return Colour::kBlue;
  if (g > 180 && r < 80 && b < 80) return Colour::kGreen;
  if (b > 180 && r > 100 && g < 80) return Colour::kViolet;
  if (r > 180 && g > 180 && b < 80) return Colour::kYellow;
  return Colour::kOther;
}

}  // namespace colony::pushpull

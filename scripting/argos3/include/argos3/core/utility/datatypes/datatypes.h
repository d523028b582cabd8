// ARGoS compatibility layer (Colony): the basic types of ARGoS's control
// interface. Real is double, as in ARGoS's default build (ARGOS_USE_DOUBLE).
#pragma once

#include <cstddef>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

namespace argos {

using Real = double;
using SInt8 = int8_t;
using UInt8 = uint8_t;
using SInt16 = int16_t;
using UInt16 = uint16_t;
using SInt32 = int32_t;
using UInt32 = uint32_t;
using SInt64 = int64_t;
using UInt64 = uint64_t;

// As in ARGoS, one-byte integers print as numbers, not characters.
inline std::ostream& operator<<(std::ostream& os, const SInt8 value) {
  return os << static_cast<int>(value);
}
inline std::ostream& operator<<(std::ostream& os, const UInt8 value) {
  return os << static_cast<unsigned>(value);
}

}  // namespace argos

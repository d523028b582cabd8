// The robot's internal bus, as seed 000 (section 3.3.3) counts it: what
// polling a sensor from the main computer and receiving its events cost in
// bytes. Used by the host's bus accounting (<sensor bus="true">,
// docs/events.md).
#pragma once

#include <cstdint>

namespace colony {

// The marXbot's ASEBA bus (seed 000): 2 bytes per value (S), 3 bytes of
// header per message (O: source identifier + message type).
inline constexpr uint64_t kBusValueBytes = 2;
inline constexpr uint64_t kBusOverheadBytes = 3;

// One poll of a sensor of `values` values (C), with the two motor commands
// that follow it: (C S + O) + 2 (S + O). The proximity ring (C = 24): 61 B;
// at f polls a second, f times that (67 Hz: 4,087 B/s).
constexpr uint64_t BusPollBytes(uint64_t values, uint64_t value_bytes = kBusValueBytes,
                                uint64_t overhead = kBusOverheadBytes) {
  return (values * value_bytes + overhead) + 2 * (value_bytes + overhead);
}

// One event: the index of the reading that crossed and its value, in one
// message (2 S + O = 7 B, the size of the seed's ObstacleDetected event
// with its two arguments). The motors subscribe to events themselves in the
// seed's setup (its appendix B.1), so no motor commands are counted.
constexpr uint64_t BusEventBytes(uint64_t value_bytes = kBusValueBytes,
                                 uint64_t overhead = kBusOverheadBytes) {
  return 2 * value_bytes + overhead;
}

}  // namespace colony

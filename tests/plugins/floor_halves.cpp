// Test loop functions that colour the floor (<floor source="loop_functions">):
// black where x < 0, white elsewhere, and a grey disc of radius 0.25 m
// around (1, 1).
#include <cmath>

#include "core/loop_functions.h"

namespace {

class FloorHalves : public colony::LoopFunctions {
 public:
  bool DrawsFloor() const override { return true; }
  colony::Color FloorColor(double x, double y) override {
    if (std::hypot(x - 1, y - 1) < 0.25) return colony::Color{128, 128, 128, 255};
    return x < 0 ? colony::Color::Black() : colony::Color::White();
  }
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    FloorHalves, "floor_halves",
    "test: a floor black for x < 0, white elsewhere, grey disc at (1, 1)", {});

}  // namespace

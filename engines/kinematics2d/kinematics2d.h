// kinematics2d's interface to the physics models of entity types
// (core/engine.h). The engine knows two kinds of entity: discs driven by the
// differential drive of their DriveState component (moved, blocked, never
// overlapping), and obstacles (read from the space, never moved). A model
// says which its entity type is.
#pragma once

#include "core/engine.h"

namespace colony {

class Kinematics2dModel : public PhysicsModel {
 public:
  // True: the engine moves the type's entities as discs (the footprint's
  // bounding circle) driven by their DriveState; false: they are fixed
  // obstacles, movable or not.
  virtual bool driven() const = 0;
};

// The model of a type that is only an obstacle in kinematics2d.
class Kinematics2dObstacleModel : public Kinematics2dModel {
 public:
  bool driven() const override { return false; }
};

// The model of a type whose entities are discs driven by differential drive.
class Kinematics2dDrivenDiscModel : public Kinematics2dModel {
 public:
  bool driven() const override { return true; }
};

}  // namespace colony

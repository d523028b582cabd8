// pointmass3d's interface to the physics models of entity types
// (core/engine.h). The engine knows two kinds of entity: flyers, point
// masses pushed by the rotors of their QuadrotorState (the eye-bot's flight
// computer, entities/eyebot/flight.h) and kept out of everything solid as
// upright cylinders of their geometry; and obstacles (read from the space,
// never moved). A model says which its entity type is.
#pragma once

#include "core/engine.h"

namespace colony {

class Pointmass3dModel : public PhysicsModel {
 public:
  // True: the engine flies the type's entities (they must carry a
  // QuadrotorState; a CeilingAttachmentState, if they have one, lets them
  // hold to the ceiling); false: they are fixed obstacles, movable or not.
  virtual bool flyer() const = 0;
};

// The model of a type that is only an obstacle in pointmass3d.
class Pointmass3dObstacleModel : public Pointmass3dModel {
 public:
  bool flyer() const override { return false; }
};

// The model of a type whose entities fly.
class Pointmass3dFlyerModel : public Pointmass3dModel {
 public:
  bool flyer() const override { return true; }
};

}  // namespace colony

// Passive things: box, cylinder, construction cube, light, landmark, pocket.
#include "core/entity_type.h"
#include "entities/objects/pocket.h"

namespace colony {
namespace {

void ReadSolid(const ConfigNode& node, EntityDesc& desc, Color default_color) {
  const bool movable = node.GetBool("movable", false);
  desc.init.flags = movable ? (kSolid | kMovable) : kSolid;
  desc.init.mass = node.GetDouble("mass", movable ? 1.0 : 0.0, Range::NonNegative());
  if (movable && node.Has("mass") && desc.init.mass <= 0) {
    node.Error("mass", node.GetString("mass", ""), "a movable object needs a mass > 0 (kg)");
  }
  desc.init.color = node.GetColor("color", default_color);
}

const std::vector<AttributeDoc> kSolidAttributes = {
    {"movable", "true, false", "false", "whether engines may move it (kinematics2d never does)"},
    {"mass", "a number >= 0 (kg)", "1 if movable", "mass for dynamics engines"},
    {"color", kColorAccepted, "gray50 / gray70", "colour seen by cameras and renderers"},
};

class BoxType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    const auto size = node.RequireTriple("size", Range::Positive());
    desc.init.geometry.shape = ShapeKind::kBox;
    desc.init.geometry.size = Vec3(size[0], size[1], size[2]);
    desc.init.geometry.radius = desc.init.geometry.BoundingRadius();
    ReadSolid(node, desc, Color{128, 128, 128, 255});
  }
};

std::vector<AttributeDoc> BoxAttributes() {
  std::vector<AttributeDoc> a = {{"size", "\"x,y,z\" > 0 (m)", "", "full size along x, y, z"}};
  a.insert(a.end(), kSolidAttributes.begin(), kSolidAttributes.end());
  return a;
}

COLONY_REGISTER_ENTITY(BoxType, "box", "a box: wall or obstacle, movable or not; takes <body>",
                       BoxAttributes(), {});

class CylinderType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    const double radius = node.RequireDouble("radius", Range::Positive());
    const double height = node.RequireDouble("height", Range::Positive());
    desc.init.geometry.shape = ShapeKind::kCylinder;
    desc.init.geometry.radius = radius;
    desc.init.geometry.size = Vec3(2 * radius, 2 * radius, height);
    ReadSolid(node, desc, Color{179, 179, 179, 255});
  }
};

std::vector<AttributeDoc> CylinderAttributes() {
  std::vector<AttributeDoc> a = {{"radius", "a number > 0 (m)", "", "radius"},
                                 {"height", "a number > 0 (m)", "", "height"}};
  a.insert(a.end(), kSolidAttributes.begin(), kSolidAttributes.end());
  return a;
}

COLONY_REGISTER_ENTITY(CylinderType, "cylinder",
                       "an upright cylinder: obstacle, movable or not; takes <body>",
                       CylinderAttributes(), {});

// The construction cube (seeds 000 and 001): 6 cm of light polystyrene with
// ferromagnetic plates low on its sides (the manipulator's magnet holds it),
// magnets underneath and plates on top, so that a cube dropped on another
// self-aligns and stays on it. Always movable. Engines that simulate magnets
// (dynamics3d) know the type by its label "cube".
class CubeType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    const double side = node.GetDouble("size", 0.06, Range::Positive());
    desc.init.geometry.shape = ShapeKind::kBox;
    desc.init.geometry.size = Vec3(side, side, side);
    desc.init.geometry.radius = desc.init.geometry.BoundingRadius();
    desc.init.flags = kSolid | kMovable;
    desc.init.mass = node.GetDouble("mass", 0.04, Range::Positive());
    desc.init.color = node.GetColor("color", Color{240, 240, 240, 255});
  }
};

COLONY_REGISTER_ENTITY(
    CubeType, "cube",
    "a construction cube: 6 cm, light, held by the manipulator's magnet, self-aligning "
    "when stacked; always movable; takes <body>",
    (std::vector<AttributeDoc>{
        {"size", "a number > 0 (m)", "0.06", "side"},
        {"mass", "a number > 0 (kg)", "0.04", "mass (polystyrene with steel plates and magnets)"},
        {"color", kColorAccepted, "240,240,240", "colour; the tops are the brightest surfaces"},
    }),
    (std::vector<std::string>{"construction_cube"}));

class LightType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    const auto p = node.RequireTriple("position");
    const auto o = node.GetTriple("orientation", {0, 0, 0});
    desc.init.pose.position = Vec3(p[0], p[1], p[2]);
    desc.init.pose.orientation = FromEulerZYX(DegToRad(o[0]), DegToRad(o[1]), DegToRad(o[2]));
    desc.init.flags = 0;  // not solid: nothing collides with it
    desc.init.color = node.GetColor("color", Color{255, 255, 0, 255});
    desc.init.light_intensity = node.GetDouble("intensity", 1.0, Range::Positive());
    desc.init.led_count = 1;
    node.GetString("medium", "");
  }
  bool has_body() const override { return false; }
};

COLONY_REGISTER_ENTITY(LightType, "light", "a point light that light sensors see; not solid",
                       (std::vector<AttributeDoc>{
                           {"position", "\"x,y,z\" (m)", "", "where the light is"},
                           {"orientation", "\"yaw,pitch,roll\" (degrees)", "0,0,0",
                            "direction (unused by point lights)"},
                           {"color", kColorAccepted, "yellow", "colour of the light"},
                           {"intensity", "a number > 0", "1", "relative intensity"},
                           {"medium", "a medium id", "none", "accepted for ARGoS files; unused"},
                       }),
                       {});

// A landmark (seed 004): a coloured post, a solid upright cylinder robots
// stop at, that the omnidirectional camera sees as one blob at its centre
// (media/led). Never movable.
class LandmarkType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    const double radius = node.GetDouble("radius", kLandmarkRadius, Range::Positive());
    const double height = node.GetDouble("height", 0.2, Range::Positive());
    desc.init.geometry.shape = ShapeKind::kCylinder;
    desc.init.geometry.radius = radius;
    desc.init.geometry.size = Vec3(2 * radius, 2 * radius, height);
    desc.init.flags = kSolid;
    desc.init.color = node.GetColor("color", Color{0, 255, 0, 255});
  }

 private:
  // The seed gives no size; a post 6 cm across, as the renderer always drew it.
  static constexpr double kLandmarkRadius = 0.03;  // m
};

COLONY_REGISTER_ENTITY(
    LandmarkType, "landmark",
    "a coloured post: a solid upright cylinder that the omnidirectional camera sees as one "
    "blob at its centre; never movable; takes <body>",
    (std::vector<AttributeDoc>{
        {"radius", "a number > 0 (m)", "0.03", "radius of the post"},
        {"height", "a number > 0 (m)", "0.2", "height of the post; the blob is at half of it"},
        {"color", kColorAccepted, "green", "colour of the blob (black: not seen)"},
    }),
    {});

// The deformable pocket of seed 004 (pocket.h): a bag of rice, 12 x 7 x 1.5
// cm, red. Movable (the manipulator carries it) and solid (ray sensors see
// it), but no engine pushes it: it lies where it was put down, on the heap
// model's height (entities/objects/README.md, "Pockets").
class PocketType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    desc.init.geometry.shape = ShapeKind::kBox;
    desc.init.geometry.size = Vec3(pocket::kLength, pocket::kWidth, pocket::kThickness);
    desc.init.geometry.radius = desc.init.geometry.BoundingRadius();
    desc.init.flags = kSolid | kMovable;
    desc.init.mass = node.GetDouble("mass", pocket::kMass, Range::Positive());
    desc.init.color = node.GetColor("color", Color{255, 0, 0, 255});
    PocketState state;
    state.threshold = node.GetDouble("occlusion_threshold", 100 * pocket::kOcclusionThreshold,
                                     Range::Between(0, 100)) /
                      100;
    desc.init.components.Add(state);
  }
  void Placed(Space& space) const override { SettlePendingPockets(space); }
};

COLONY_REGISTER_ENTITY(
    PocketType, "pocket",
    "a deformable pocket (seed 004): a 12 x 7 x 1.5 cm bag of rice, red, held by the "
    "manipulator's magnet; settles on the pockets under it; invisible to cameras once covered "
    "beyond its occlusion threshold; takes <body>",
    (std::vector<AttributeDoc>{
        {"mass", "a number > 0 (kg)", "0.1", "mass"},
        {"color", kColorAccepted, "red", "colour seen by cameras (black: not seen)"},
        {"occlusion_threshold", "a number in [0, 100] (%)", "75",
         "invisible to cameras once more than this much of its top is covered by pockets"},
    }),
    {});

}  // namespace
}  // namespace colony

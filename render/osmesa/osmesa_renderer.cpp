// The "osmesa" renderer: PNG frames of the space, drawn off-screen every K
// ticks from the cameras of its <camera> children (by default one camera over
// the whole arena), entities dressed with the meshes of its <mesh> children.
#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/log.h"
#include "core/renderer.h"
#include "core/simulation.h"
#include "render/osmesa/mesh.h"
#include "render/osmesa/offscreen.h"
#include "render/osmesa/overlays.h"
#include "render/osmesa/scene.h"

namespace colony::render {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kMaxBufferSide = 8192;    // pixels, image size x antialias
constexpr double kDefaultTilt = 30;     // degrees from the vertical, default camera
constexpr double kFineFromPixels = 10;  // entities drawn coarse below this radius in pixels

Vec3 ToVec3(const std::array<double, 3>& a) { return Vec3(a[0], a[1], a[2]); }

// Where a message about an element points.
struct Origin {
  int line = 0;
  std::string label;  // "camera id=\"top\""
};

struct Camera {
  std::string id;
  Vec3 position = Vec3::Zero(), look_at = Vec3::Zero();
  std::optional<Vec3> up;  // default: z up, or y for a camera looking straight down
  double fov = 60;
  std::string follow;  // entity id; position, look_at and up are then in its frame
  EntityHandle followed;
  Pose follow_pose;  // the followed entity's last pose
  Origin origin;
  std::optional<View> overview;  // the default camera's fixed view
};

struct MeshReference {
  std::string entity;  // an entity id, checked once the arena exists
  Origin origin;
};

// The up vector of a camera looking along `direction` when none is given.
Vec3 DefaultUp(const Vec3& direction) {
  return std::abs(direction.normalized().z()) > 0.999 ? Vec3::UnitY() : Vec3::UnitZ();
}

bool Parallel(const Vec3& a, const Vec3& b) {
  return a.normalized().cross(b.normalized()).norm() < 1e-6;
}

bool IsFileNameSafe(const std::string& id) {
  return !id.empty() && std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

// Near and far planes that hold the arena, whatever the camera's distance.
void FitClipPlanes(const Space& space, View& view) {
  double far = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1 ? space.arena_max() : space.arena_min()).x(),
                      (k & 2 ? space.arena_max() : space.arena_min()).y(),
                      (k & 4 ? space.arena_max() : space.arena_min()).z());
    far = std::max(far, (corner - view.eye).norm());
  }
  view.far_clip = 1.1 * far + 1;
  view.near_clip = std::clamp(0.05 * (view.target - view.eye).norm(), 0.005, 1.0);
}

// Tallest top of any solid entity, at least the floor.
double TopOfSolids(const Space& space) {
  double top = space.arena_min().z();
  for (uint32_t i = 0; i < space.slots(); ++i) {
    if (space.alive(i) && (space.flags(i) & kSolid)) {
      top = std::max(top, space.pose(i).position.z() + space.geometry(i).height());
    }
  }
  return top;
}

// A camera over the arena's centre, tilted from the south, just far enough
// for the whole arena (and everything standing on it) to fit.
View OverviewView(const Space& space, int width, int height) {
  const Vec3 lo = space.arena_min(), hi = space.arena_max();
  const double top = TopOfSolids(space);
  View view;
  view.width = width;
  view.height = height;
  view.fov = 60;
  view.target = Vec3((lo.x() + hi.x()) / 2, (lo.y() + hi.y()) / 2, lo.z());
  const Vec3 back(0, -std::sin(DegToRad(kDefaultTilt)), std::cos(DegToRad(kDefaultTilt)));
  auto fits = [&](double distance) {
    view.eye = view.target + distance * back;
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? top : lo.z());
      const auto p = view.ToPixel(corner);
      if (!p || p->x() < 0.04 * width || p->x() > 0.96 * width || p->y() < 0.04 * height ||
          p->y() > 0.96 * height) {
        return false;
      }
    }
    return true;
  };
  double near = 0.01, far = 1e5;
  for (int k = 0; k < 60; ++k) {
    const double mid = std::sqrt(near * far);
    (fits(mid) ? far : near) = mid;
  }
  fits(far);
  FitClipPlanes(space, view);
  return view;
}

class OsmesaRenderer : public Renderer {
 public:
  void Configure(const ConfigNode& node) override {
    file_ = node.file();
    width_ = static_cast<int>(node.GetInt("width", 1280, 16, kMaxBufferSide));
    height_ = static_cast<int>(node.GetInt("height", 720, 16, kMaxBufferSide));
    every_ = static_cast<uint64_t>(node.GetInt("every", 1, 1));
    antialias_ = static_cast<int>(node.GetInt("antialias", 2, 1, 4));
    background_ = node.GetColor("background", Color{215, 222, 230, 255});
    grid_ = node.GetDouble("grid", 1.0, Range::NonNegative());
    ids_ = node.GetBool("ids", false);
    draw_trails_ = node.GetBool("trails", false);
    trail_ticks_ = static_cast<int>(node.GetInt("trail_ticks", 100, 2, 1'000'000));
    proximity_rays_ = node.GetBool("proximity_rays", false);
    if (std::max(width_, height_) * antialias_ > kMaxBufferSide) {
      node.Error("antialias", node.GetString("antialias", "2"),
                 "the image drawn before averaging would be over " +
                     std::to_string(kMaxBufferSide) +
                     " pixels wide; accepted: antialias x max(width, height) <= " +
                     std::to_string(kMaxBufferSide));
    }
    if (grid_ > 0 && grid_ < 0.01) {
      node.Error("grid", node.GetString("grid", ""),
                 "grid lines closer than 1 cm; accepted: 0 (no grid) or >= 0.01 (m)");
    }
    node.CheckChildren({"camera", "mesh"});
    for (const ConfigNode& c : node.Children("camera")) ReadCamera(c);
    for (const ConfigNode& m : node.Children("mesh")) ReadMesh(m);
  }

  void AfterTick() override {
    if (!renderer_) Start();
    if (trails_) trails_->Record(sim().space());
    if (sim().tick() % every_ != 0) return;
    const auto t0 = Clock::now();
    views_.clear();
    for (Camera& camera : cameras_) views_.push_back(ViewOf(camera));
    BuildScene();
    draw_seconds_ += Seconds(t0);
    for (size_t k = 0; k < cameras_.size(); ++k) DrawFrame(cameras_[k].id, views_[k]);
    ++frames_;
  }

  void Finish() override {
    if (frames_ == 0) return;
    const double images = static_cast<double>(frames_ * cameras_.size());
    std::ostringstream message;
    message << std::fixed << std::setprecision(1) << "osmesa: " << frames_ << " frame(s) x "
            << cameras_.size() << " camera(s) in " << output_dir() << " (" << width_ << " x "
            << height_ << ": " << 1e3 * draw_seconds_ / images << " ms drawing + "
            << 1e3 * write_seconds_ / images << " ms writing per image)";
    LogInfo(message.str());
  }

  std::vector<FrameSeries> frame_series() const override {
    std::vector<FrameSeries> out;
    for (const Camera& c : cameras_) {
      out.push_back({c.id, (fs::path(output_dir()) / (c.id + "_%06d.png")).string(), frames_,
                     1.0 / (sim().dt() * static_cast<double>(every_))});
    }
    return out;
  }

 private:
  void ReadCamera(const ConfigNode& c) {
    c.CheckAttributes({"id", "position", "look_at", "up", "fov", "follow"});
    c.CheckChildren({});
    Camera camera;
    camera.origin = {c.line(), c.Label()};
    camera.id = c.GetString("id", "camera" + std::to_string(cameras_.size()));
    if (!IsFileNameSafe(camera.id)) {
      c.Error("id", camera.id,
              "'" + camera.id + "' cannot name frame files; accepted: letters, digits, _ - .");
    }
    for (const Camera& other : cameras_) {
      if (other.id == camera.id) {
        c.Error("id", camera.id,
                "camera id '" + camera.id + "' already used at line " +
                    std::to_string(other.origin.line));
      }
    }
    camera.position = ToVec3(c.RequireTriple("position"));
    camera.look_at = ToVec3(c.RequireTriple("look_at"));
    camera.fov = c.GetDouble("fov", 60, Range{0, 179, true});
    camera.follow = c.GetString("follow", "");
    const Vec3 direction = camera.look_at - camera.position;
    if (c.Has("position") && c.Has("look_at") && direction.norm() < 1e-9) {
      c.Error("look_at", c.GetString("look_at", ""),
              "look_at is the camera's position, so the camera looks nowhere; accepted: a point "
              "other than position");
    } else if (c.Has("up")) {
      camera.up = ToVec3(c.GetTriple("up", {0, 0, 1}));
      if (camera.up->norm() < 1e-9 || Parallel(*camera.up, direction)) {
        c.Error("up", c.GetString("up", ""),
                "up must not be zero or parallel to the viewing direction (look_at - position); "
                "accepted: a "
                "vector across it, e.g. 0,0,1 (0,1,0 for a camera looking straight down)");
      }
    }
    cameras_.push_back(std::move(camera));
  }

  void ReadMesh(const ConfigNode& m) {
    m.CheckAttributes({"type", "entity", "file", "scale", "position", "orientation", "color"});
    m.CheckChildren({});
    if (m.Has("type") == m.Has("entity")) {
      m.ElementError(
          "give exactly one of type=\"LABEL\" (every entity of that type, e.g. marxbot) or "
          "entity=\"ID\"");
      return;
    }
    MeshPlacement placement;
    placement.scale = m.GetDouble("scale", 1, Range::Positive());
    placement.offset.position = ToVec3(m.GetTriple("position", {0, 0, 0}));
    const auto o = m.GetTriple("orientation", {0, 0, 0});
    placement.offset.orientation = FromEulerZYX(DegToRad(o[0]), DegToRad(o[1]), DegToRad(o[2]));
    if (m.Has("color")) placement.color = m.GetColor("color", Color::White());
    const std::string file = m.RequireString("file");
    if (file.empty()) return;
    auto mesh = std::make_shared<Mesh>();
    if (const std::string error = LoadMesh(ResolvePath(file), placement, *mesh); !error.empty()) {
      m.Error("file", file,
              error + "; accepted: a mesh file assimp reads (OBJ, glTF, STL, COLLADA, ...)");
      return;
    }
    if (m.Has("entity")) {
      const std::string id = m.GetString("entity", "");
      meshes_.BindEntity(id, mesh);
      mesh_entities_.push_back({id, {m.line(), m.Label()}});
      return;
    }
    const std::string type = m.GetString("type", "");
    const auto* entry = Registry<EntityType>::Get().Find(type);
    if (!entry) {
      std::string labels;
      for (const auto& l : Registry<EntityType>::Get().Labels())
        labels += (labels.empty() ? "" : ", ") + l;
      m.Error("type", type, "no entity type '" + type + "'; accepted: " + labels);
      return;
    }
    meshes_.BindType(entry->info.label, mesh);
  }

  // A relative path is looked up beside the experiment file first.
  std::string ResolvePath(const std::string& file) const {
    const fs::path p(file);
    if (p.is_absolute()) return file;
    const fs::path beside = fs::path(sim().file()).parent_path() / p;
    std::error_code ec;
    return fs::exists(beside, ec) ? beside.string() : file;
  }

  // Once the arena exists: entity references, default camera, output folder.
  void Start() {
    CheckEntityReferences();
    if (output_dir().empty()) {
      throw RuntimeFailure("renderer <osmesa> in " + file_ + " has no folder to write frames to");
    }
    std::error_code ec;
    fs::create_directories(output_dir(), ec);
    if (ec) {
      throw RuntimeFailure("cannot create the frames folder '" + output_dir() +
                           "': " + ec.message());
    }
    if (cameras_.empty()) {
      Camera overview;
      overview.id = "camera0";
      overview.overview = OverviewView(sim().space(), width_, height_);
      cameras_.push_back(std::move(overview));
    }
    if (draw_trails_) trails_ = std::make_unique<Trails>(trail_ticks_);
    renderer_ = std::make_unique<OffscreenRenderer>();
  }

  void CheckEntityReferences() {
    std::vector<Diagnostic> problems;
    const Space& space = sim().space();
    for (Camera& c : cameras_) {
      if (c.follow.empty()) continue;
      c.followed = space.Find(c.follow);
      if (!c.followed.valid()) {
        problems.push_back(
            {file_, c.origin.line, c.origin.label, "follow", c.follow,
             "no entity '" + c.follow + "' in the arena; accepted: the id of an entity"});
      } else {
        c.follow_pose = space.pose(c.followed.index);
      }
    }
    for (const MeshReference& m : mesh_entities_) {
      if (!space.Find(m.entity).valid()) {
        problems.push_back(
            {file_, m.origin.line, m.origin.label, "entity", m.entity,
             "no entity '" + m.entity + "' in the arena; accepted: the id of an entity"});
      }
    }
    if (!problems.empty()) throw ConfigError(std::move(problems));
  }

  void BuildScene() {
    const Space& space = sim().space();
    const SceneBuilder builder(sim(), &meshes_);
    batch_.Clear();
    if (grid_ > 0) AddGrid(space, grid_, batch_);
    if (trails_) trails_->AddTo(space, batch_);
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (!space.alive(i)) continue;
      builder.AddEntity(i, batch_, DetailOf(i));
      if (proximity_rays_ && (space.flags(i) & kRobot)) AddProximityRays(sim(), i, batch_);
    }
    AddLaserSpots(sim(), batch_, true);
    DrawLoopFunctions(sim(), drawing_);
    AddDrawing(drawing_, batch_);
  }

  // Coarse when the entity is small in every camera's image.
  Detail DetailOf(uint32_t slot) const {
    const Space& space = sim().space();
    const Vec3& p = space.pose(slot).position;
    const double radius = std::max(space.geometry(slot).BoundingRadius(), 0.05);
    for (const View& view : views_) {
      if (radius * view.focal_length() >= kFineFromPixels * (p - view.eye).norm()) {
        return Detail::kFine;
      }
    }
    return Detail::kCoarse;
  }

  View ViewOf(Camera& camera) const {
    if (camera.overview) return *camera.overview;
    const Space& space = sim().space();
    if (camera.followed.valid() && space.IsAlive(camera.followed)) {
      camera.follow_pose = space.pose(camera.followed.index);
    }
    const Pose& frame = camera.follow.empty() ? Pose{} : camera.follow_pose;
    View view;
    view.width = width_;
    view.height = height_;
    view.fov = camera.fov;
    view.eye = frame.position + frame.orientation * camera.position;
    view.target = frame.position + frame.orientation * camera.look_at;
    view.up = frame.orientation * camera.up.value_or(DefaultUp(camera.look_at - camera.position));
    FitClipPlanes(space, view);
    return view;
  }

  void DrawFrame(const std::string& camera, const View& view) {
    const auto t0 = Clock::now();
    renderer_->Draw(sim().space(), batch_, view, {background_, antialias_}, image_);
    DrawPointsAndText(drawing_, view, image_);
    if (ids_) DrawRobotIds(sim().space(), view, image_);
    const auto t1 = Clock::now();
    char name[32];
    std::snprintf(name, sizeof name, "_%06llu.png", static_cast<unsigned long long>(frames_));
    const std::string error = WritePng(image_, (fs::path(output_dir()) / (camera + name)).string());
    if (!error.empty()) throw RuntimeFailure(error);
    draw_seconds_ += std::chrono::duration<double>(t1 - t0).count();
    write_seconds_ += Seconds(t1);
  }

  static double Seconds(Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
  }

  // Settings.
  std::string file_;
  int width_ = 1280, height_ = 720, antialias_ = 2, trail_ticks_ = 100;
  uint64_t every_ = 1;
  Color background_;
  double grid_ = 1;
  bool ids_ = false, draw_trails_ = false, proximity_rays_ = false;
  std::vector<Camera> cameras_;
  MeshTable meshes_;
  std::vector<MeshReference> mesh_entities_;
  // State.
  std::unique_ptr<Trails> trails_;  // when trails are on
  std::unique_ptr<OffscreenRenderer> renderer_;
  std::vector<View> views_;  // this frame's, one per camera
  SceneBatch batch_;
  DrawList drawing_;  // what the loop functions draw this frame
  Image image_;
  uint64_t frames_ = 0;
  double draw_seconds_ = 0, write_seconds_ = 0;
};

COLONY_REGISTER_RENDERER(
    OsmesaRenderer, "osmesa",
    "off-screen OpenGL (OSMesa: no display, no GPU): PNG frames every K ticks from each <camera id "
    "position "
    "look_at up fov follow> child (none: one camera over the whole arena); <mesh type|entity file "
    "scale "
    "position orientation color> children draw entities with mesh files (assimp)",
    (std::vector<AttributeDoc>{
        {"width", "a whole number in [16, 8192] (pixels)", "1280", "frame width"},
        {"height", "a whole number in [16, 8192] (pixels)", "720", "frame height"},
        {"every", "a whole number >= 1 (ticks)", "1",
         "a frame every K ticks (and one of the initial state)"},
        {"antialias", "1, 2, 3 or 4", "2",
         "draws at this many times the size and averages down; 1: off"},
        {"background", kColorAccepted, "215,222,230", "colour around the arena"},
        {"grid", "0, or a number >= 0.01 (m)", "1",
         "faint floor grid lines this far apart (farther over a large arena: at most 2000 "
         "across a side); 0: none"},
        {"ids", "true, false", "false", "writes each robot's id above it"},
        {"trails", "true, false", "false", "draws the recent path of every movable entity"},
        {"trail_ticks", "a whole number >= 2", "100", "how many ticks of path a trail shows"},
        {"proximity_rays", "true, false", "false",
         "draws the rays of robots' proximity sensors (hits in purple)"},
    }));

}  // namespace
}  // namespace colony::render

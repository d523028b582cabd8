// The osmesa backend of the image renderer (core/image_renderer.h), which
// draws the robots' camera images: the entities a view may show, as simple
// shapes (never the <mesh> files of <visualization>: what a robot senses must
// not depend on how the run is visualised), drawn by one OpenGL context.
#include "core/image_renderer.h"

#include <cmath>
#include <vector>

#include "core/simulation.h"
#include "render/osmesa/image.h"
#include "render/osmesa/offscreen.h"
#include "render/osmesa/scene.h"
#include "render/osmesa/view.h"

namespace colony::render {
namespace {

// Margin around an entity's shape when culling: LEDs and lights stand out of it.
constexpr double kLooseness = 0.05;  // m

class OsmesaImageRenderer : public ImageRenderer {
 public:
  explicit OsmesaImageRenderer(const Simulation& sim) : sim_(sim) {}

  void Render(const CameraView& camera, std::vector<uint8_t>& rgb) override {
    const View view = ViewOf(camera);
    BuildScene(view, camera.hidden);
    offscreen_.Draw(sim_.space(), batch_, view, {}, image_);
    std::swap(rgb, image_.rgb);
  }

 private:
  static View ViewOf(const CameraView& camera) {
    View view;
    view.eye = camera.position;
    view.target = view.eye + camera.orientation * Vec3::UnitX();
    view.up = camera.orientation * Vec3::UnitZ();
    view.fov = camera.fov;
    view.near_clip = camera.near_clip;
    view.far_clip = camera.far_clip;
    view.width = camera.width;
    view.height = camera.height;
    view.pixel_aspect = camera.pixel_aspect;
    return view;
  }

  // The entities that may show in `view`: solid ones within its far plane
  // (from the spatial index) and the others (lights), unless wholly outside
  // the view; never `hidden`; and the laser spots.
  void BuildScene(const View& view, EntityHandle hidden) {
    const Space& space = sim_.space();
    const double range = view.far_clip;
    nearby_.clear();
    space.Gather(view.eye.x() - range, view.eye.y() - range, view.eye.x() + range,
                 view.eye.y() + range, nearby_);
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (space.alive(i) && !(space.flags(i) & kSolid)) nearby_.push_back(i);
    }
    const Frustum frustum(view);
    const SceneBuilder builder(sim_, nullptr);
    batch_.Clear();
    for (uint32_t i : nearby_) {
      if (space.HandleOf(i) == hidden) continue;
      const Geometry& g = space.geometry(i);
      const Vec3 center = space.pose(i).position + Vec3(0, 0, g.height() / 2);
      const double radius = std::hypot(g.BoundingRadius(), g.height() / 2) + kLooseness;
      if (frustum.MayShow(center, radius)) builder.AddEntity(i, batch_);
    }
    // Laser spots, wherever their robots are (no beams: invisible in clean air).
    AddLaserSpots(sim_, batch_, false);
  }

  const Simulation& sim_;
  OffscreenRenderer offscreen_;
  std::vector<uint32_t> nearby_;
  SceneBatch batch_;
  Image image_;
};

COLONY_REGISTER_IMAGE_RENDERER(OsmesaImageRenderer);

}  // namespace
}  // namespace colony::render

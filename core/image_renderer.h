// Image renderers: what draws the images that camera sensors read. Core
// declares the interface; a backend (render/osmesa: OpenGL with no display
// and no GPU) implements it in a plugin, libcolony_osmesa.so, which installs
// its factory with COLONY_REGISTER_IMAGE_RENDERER when loaded. Core loads it
// from the plugin folders the first time HaveImageRenderer or
// MakeImageRenderer is called, so a run that draws nothing never loads
// OSMesa. A build may have none (-DCOLONY_WITH_OSMESA=OFF): whatever needs
// images then says so at load, with NoImageRendererMessage.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/registry.h"
#include "core/space.h"

namespace colony {

class Simulation;

// A pinhole camera in the space, and what it must not show.
struct CameraView {
  Vec3 position = Vec3::Zero();             // the eye (m, world frame)
  Quat orientation = Quat::Identity();      // x: the optical axis; z: up in the image
  double fov = 60;                          // horizontal field of view (degrees), in (0, 180)
  double near_clip = 0.01, far_clip = 100;  // m; nothing nearer or farther is drawn
  int width = 640, height = 480;            // pixels
  double pixel_aspect = 1;                  // a pixel's width over its height
  EntityHandle hidden;  // an entity not drawn (e.g. the robot carrying the camera); none by default
};

// Draws what a camera sees: the floor (colour or image), every entity within
// far_clip as simple shapes in its colours, LEDs and lights glowing; black
// where nothing is. Reads the space only.
//
// One object draws one image at a time: callers that draw from several
// threads serialise their calls. It may move between threads, and it leaves
// the calling thread's floating-point environment as it found it, so drawing
// cannot change the simulation's numbers.
class ImageRenderer {
 public:
  virtual ~ImageRenderer() = default;
  // Sets `rgb` to the image: width x height x 3 bytes (red, green, blue,
  // 0..255), rows from the top, pixels from the left. Throws RuntimeFailure
  // when the backend cannot draw.
  virtual void Render(const CameraView& view, std::vector<uint8_t>& rgb) = 0;
};

// Makes an image renderer that draws `sim`'s space (read only; `sim` must
// outlive it).
using ImageRendererFactory = std::unique_ptr<ImageRenderer> (*)(const Simulation& sim);

// Installs `factory` as this build's image renderer and returns the one it
// replaces. The backend calls it once, when its plugin loads; nullptr removes
// it (tests use that to see what a build without one does: they call
// HaveImageRenderer first, so the plugin is loaded and does not install
// itself afterwards). A factory set before the plugin was loaded keeps it
// from being loaded.
ImageRendererFactory SetImageRendererFactory(ImageRendererFactory factory);
// Whether this build has an image renderer (loads the backend's plugin on
// the first call; thread-safe).
bool HaveImageRenderer();
// A new image renderer for `sim`. Throws RuntimeFailure, with
// NoImageRendererMessage, when this build has none.
std::unique_ptr<ImageRenderer> MakeImageRenderer(const Simulation& sim);
// "<who> needs an image renderer, and this build has none: configure with
// -DCOLONY_WITH_OSMESA=ON (...)": `who` is e.g. "the camera sensor".
std::string NoImageRendererMessage(const std::string& who);

struct ImageRendererRegistrar {
  explicit ImageRendererRegistrar(ImageRendererFactory factory) {
    SetImageRendererFactory(factory);
  }
};

// COLONY_REGISTER_IMAGE_RENDERER(MyImageRenderer), in the backend's .cpp: the
// class has a constructor taking `const Simulation&`.
#define COLONY_REGISTER_IMAGE_RENDERER(CLASS)                                                     \
  static const ::colony::ImageRendererRegistrar COLONY_PLUGIN_CONCAT(                             \
      colony_image_renderer_,                                                                     \
      __LINE__)([](const ::colony::Simulation& sim) -> std::unique_ptr<::colony::ImageRenderer> { \
    return std::make_unique<CLASS>(sim);                                                          \
  })

}  // namespace colony

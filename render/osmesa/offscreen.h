// Drawing with OSMesa: OpenGL into a buffer in main memory, with no display,
// no X server and no GPU (Mesa's llvmpipe rasteriser on the CPU).
#pragma once

#include <string>
#include <vector>

#include "core/color.h"
#include "core/space.h"
#include "render/osmesa/image.h"
#include "render/osmesa/scene.h"
#include "render/osmesa/view.h"

struct osmesa_context;

namespace colony::render {

struct DrawOptions {
  Color background = Color::Black();
  // Draws at this many times the image's size and averages the pixels down
  // (anti-aliasing); 1 draws at the image's size.
  int supersample = 1;
};

// One OpenGL context and its buffer. Use it from one thread at a time; it
// may move between threads (it is made current for each Draw and released).
// A ditch's bottom and walls (render/osmesa draws them dark whatever the
// floor's colour: a camera sees a ditch as a dark band).
inline constexpr Color kDitchBottomColor{20, 20, 22, 255};
inline constexpr Color kDitchWallColor{45, 45, 50, 255};

class OffscreenRenderer {
 public:
  // Throws RuntimeFailure when OSMesa cannot make a context.
  OffscreenRenderer();
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // Draws the floor of `space` and `batch` as seen from `view` into `image`
  // (resized to view.width x view.height). Leaves the floating-point
  // environment of the calling thread as it was.
  void Draw(const Space& space, const SceneBatch& batch, const View& view,
            const DrawOptions& options, Image& image);

 private:
  void Activate(int width, int height);
  void DrawFloor(const Space& space);
  void DrawFloorWithDitches(const Space& space);
  void UpdateFloorTexture(const Space& space);
  void ReadBack(int supersample, Image& image) const;

  osmesa_context* context_ = nullptr;
  std::vector<uint8_t> buffer_;  // RGBA, bottom row first
  int buffer_width_ = 0, buffer_height_ = 0;
  unsigned floor_texture_ = 0;
  std::string floor_texture_key_;  // what the texture was made from
};

}  // namespace colony::render

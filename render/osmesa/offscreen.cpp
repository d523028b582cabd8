#include "render/osmesa/offscreen.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <array>
#include <cfenv>

#include "core/error.h"

namespace colony::render {
namespace {

// Texels along the longer side of the arena for a floor image.
constexpr int kFloorTextureSize = 1024;

// Mesa's rasteriser may change rounding or denormal modes; the simulation's
// results must not depend on whether it ran.
class FpEnvironmentGuard {
 public:
  FpEnvironmentGuard() { std::fegetenv(&saved_); }
  ~FpEnvironmentGuard() { std::fesetenv(&saved_); }

 private:
  std::fenv_t saved_;
};

void DrawArrays(GLenum mode, const std::vector<Vertex>& vertices) {
  if (vertices.empty()) return;
  glVertexPointer(3, GL_FLOAT, sizeof(Vertex), &vertices[0].x);
  glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(Vertex), &vertices[0].r);
  glDrawArrays(mode, 0, static_cast<GLsizei>(vertices.size()));
}

// Averages each S x S block of the RGBA buffer (bottom row first) into one
// pixel of `image` (top row first).
template <int S>
void Downsample(const std::vector<uint8_t>& buffer, int width, int height, Image& image) {
  constexpr unsigned kArea = S * S;
  for (int y = 0; y < image.height; ++y) {
    const uint8_t* rows[S];
    for (int k = 0; k < S; ++k)
      rows[k] = buffer.data() + static_cast<size_t>(height - 1 - (y * S + k)) * width * 4;
    uint8_t* out = image.Pixel(0, y);
    for (int x = 0; x < image.width; ++x, out += 3) {
      for (int c = 0; c < 3; ++c) {
        unsigned sum = 0;
        for (int ky = 0; ky < S; ++ky) {
          for (int kx = 0; kx < S; ++kx) sum += rows[ky][(x * S + kx) * 4 + c];
        }
        out[c] = static_cast<uint8_t>((sum + kArea / 2) / kArea);
      }
    }
  }
}

}  // namespace

OffscreenRenderer::OffscreenRenderer() {
  const FpEnvironmentGuard fp_guard;
  context_ = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!context_) throw RuntimeFailure("OSMesa cannot create an off-screen OpenGL context");
}

OffscreenRenderer::~OffscreenRenderer() { OSMesaDestroyContext(context_); }

void OffscreenRenderer::Activate(int width, int height) {
  if (width != buffer_width_ || height != buffer_height_) {
    buffer_.assign(static_cast<size_t>(width) * height * 4, 0);
    buffer_width_ = width;
    buffer_height_ = height;
  }
  if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
    throw RuntimeFailure("OSMesa cannot draw a " + std::to_string(width) + " x " +
                         std::to_string(height) + " image");
  }
}

void OffscreenRenderer::Draw(const Space& space, const SceneBatch& batch, const View& view,
                             const DrawOptions& options, Image& image) {
  const FpEnvironmentGuard fp_guard;
  const int s = options.supersample;
  Activate(view.width * s, view.height * s);
  glViewport(0, 0, buffer_width_, buffer_height_);
  const Color bg = options.background;
  glClearColor(bg.r / 255.0f, bg.g / 255.0f, bg.b / 255.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(view.ProjectionMatrix().data());
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(view.ViewMatrix().data());
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  // The floor and what lies on it first, without depth: everything else
  // stands on it.
  glDisable(GL_DEPTH_TEST);
  DrawFloor(space);
  glEnable(GL_BLEND);
  glLineWidth(static_cast<float>(s));
  DrawArrays(GL_LINES, batch.floor_lines);
  glLineWidth(static_cast<float>(2 * s));
  DrawArrays(GL_LINES, batch.wide_floor_lines);
  glLineWidth(static_cast<float>(s));
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  DrawArrays(GL_TRIANGLES, batch.triangles);
  glEnable(GL_BLEND);
  DrawArrays(GL_LINES, batch.lines);
  // Drawn shapes blend over what they cover without hiding what is behind them.
  glDepthMask(GL_FALSE);
  DrawArrays(GL_TRIANGLES, batch.drawn_triangles);
  glLineWidth(static_cast<float>(2 * s));
  DrawArrays(GL_LINES, batch.drawn_lines);
  glLineWidth(static_cast<float>(s));
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glFinish();
  OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
  image.Resize(view.width, view.height);
  ReadBack(s, image);
}

void OffscreenRenderer::DrawFloor(const Space& space) {
  const Vec3& lo = space.arena_min();
  const Vec3& hi = space.arena_max();
  const bool textured = space.floor().has_image();
  if (textured) {
    UpdateFloorTexture(space);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, floor_texture_);
  }
  const Color c = textured ? Color::White() : space.floor().ColorAt(lo.x(), lo.y());
  glDisableClientState(GL_COLOR_ARRAY);
  glColor4ub(c.r, c.g, c.b, 255);
  const auto& ditches = space.floor().ditches();
  if (ditches.empty()) {
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0);
    glVertex3d(lo.x(), lo.y(), lo.z());
    glTexCoord2f(1, 0);
    glVertex3d(hi.x(), lo.y(), lo.z());
    glTexCoord2f(1, 1);
    glVertex3d(hi.x(), hi.y(), lo.z());
    glTexCoord2f(0, 1);
    glVertex3d(lo.x(), hi.y(), lo.z());
    glEnd();
  } else {
    DrawFloorWithDitches(space);
  }
  glEnableClientState(GL_COLOR_ARRAY);
  glDisable(GL_TEXTURE_2D);
}

// The floor with its ditches cut out: the floor in pieces around them,
// depth-tested (pushed a little back, so what lies on the floor still shows
// over it), then each ditch's dark bottom and walls, which the floor's near
// edge hides where it should.
void OffscreenRenderer::DrawFloorWithDitches(const Space& space) {
  const Vec3& lo = space.arena_min();
  const Vec3& hi = space.arena_max();
  const Floor& floor = space.floor();
  // Cut the floor along every ditch edge; keep the cells with ground.
  std::vector<double> xs = {lo.x(), hi.x()}, ys = {lo.y(), hi.y()};
  for (const Ditch& d : floor.ditches()) {
    xs.push_back(std::clamp(d.min_x, lo.x(), hi.x()));
    xs.push_back(std::clamp(d.max_x, lo.x(), hi.x()));
    ys.push_back(std::clamp(d.min_y, lo.y(), hi.y()));
    ys.push_back(std::clamp(d.max_y, lo.y(), hi.y()));
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
  const double sx = hi.x() - lo.x(), sy = hi.y() - lo.y();
  auto vertex = [&](double x, double y, double z) {
    glTexCoord2d((x - lo.x()) / sx, (y - lo.y()) / sy);
    glVertex3d(x, y, z);
  };
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1, 1);
  glBegin(GL_QUADS);
  for (size_t i = 0; i + 1 < xs.size(); ++i) {
    for (size_t j = 0; j + 1 < ys.size(); ++j) {
      if (!floor.HasGroundAt(0.5 * (xs[i] + xs[i + 1]), 0.5 * (ys[j] + ys[j + 1]))) continue;
      vertex(xs[i], ys[j], lo.z());
      vertex(xs[i + 1], ys[j], lo.z());
      vertex(xs[i + 1], ys[j + 1], lo.z());
      vertex(xs[i], ys[j + 1], lo.z());
    }
  }
  glEnd();
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_TEXTURE_2D);
  // Bottom and walls: dark whatever the floor's colour (little light reaches
  // down there); the walls a little lighter than the bottom.
  const Color bottom = kDitchBottomColor, wall = kDitchWallColor;
  glBegin(GL_QUADS);
  for (const Ditch& d : floor.ditches()) {
    const double x0 = std::clamp(d.min_x, lo.x(), hi.x()), x1 = std::clamp(d.max_x, lo.x(), hi.x());
    const double y0 = std::clamp(d.min_y, lo.y(), hi.y()), y1 = std::clamp(d.max_y, lo.y(), hi.y());
    const double top = lo.z(), z = lo.z() - d.depth;
    glColor4ub(bottom.r, bottom.g, bottom.b, 255);
    glVertex3d(x0, y0, z);
    glVertex3d(x1, y0, z);
    glVertex3d(x1, y1, z);
    glVertex3d(x0, y1, z);
    glColor4ub(wall.r, wall.g, wall.b, 255);
    for (const auto& [ax, ay, bx, by] : {std::array{x0, y0, x1, y0}, std::array{x1, y0, x1, y1},
                                         std::array{x1, y1, x0, y1}, std::array{x0, y1, x0, y0}}) {
      glVertex3d(ax, ay, z);
      glVertex3d(bx, by, z);
      glVertex3d(bx, by, top);
      glVertex3d(ax, ay, top);
    }
  }
  glEnd();
  glDisable(GL_DEPTH_TEST);
}

// The floor image, sampled where the ground sensors read it.
void OffscreenRenderer::UpdateFloorTexture(const Space& space) {
  const Vec3& lo = space.arena_min();
  const Vec3 size = space.arena_max() - lo;
  const std::string key = space.floor().image_path() + "@" + std::to_string(lo.x()) + "," +
                          std::to_string(lo.y()) + "," + std::to_string(size.x()) + "," +
                          std::to_string(size.y());
  if (floor_texture_ && key == floor_texture_key_) return;
  const double texel = std::max(size.x(), size.y()) / kFloorTextureSize;
  const int w = std::max(1, static_cast<int>(std::lround(size.x() / texel)));
  const int h = std::max(1, static_cast<int>(std::lround(size.y() / texel)));
  std::vector<Color> texels(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      texels[static_cast<size_t>(j) * w + i] = space.floor().ColorAt(
          lo.x() + (i + 0.5) * size.x() / w, lo.y() + (j + 0.5) * size.y() / h);
    }
  }
  if (!floor_texture_) glGenTextures(1, &floor_texture_);
  glBindTexture(GL_TEXTURE_2D, floor_texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_GENERATE_MIPMAP, GL_TRUE);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
  floor_texture_key_ = key;
}

void OffscreenRenderer::ReadBack(int supersample, Image& image) const {
  switch (supersample) {
    case 1:
      return Downsample<1>(buffer_, buffer_width_, buffer_height_, image);
    case 2:
      return Downsample<2>(buffer_, buffer_width_, buffer_height_, image);
    case 3:
      return Downsample<3>(buffer_, buffer_width_, buffer_height_, image);
    default:
      return Downsample<4>(buffer_, buffer_width_, buffer_height_, image);
  }
}

}  // namespace colony::render

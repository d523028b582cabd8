// The arena floor: a flat colour or a PNG image stretched over the arena,
// read by ground sensors (grey level) and drawn by renderers; it may have
// ditches (rectangular trenches) that 3D engines cut out of the ground.
#pragma once

#include <string>
#include <vector>

#include "core/color.h"

namespace colony {

// An axis-aligned rectangular trench in the floor, [min_x, max_x] x
// [min_y, max_y], `depth` deep below the floor's surface (z = arena bottom).
struct Ditch {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  double depth = 0;
  bool Contains(double x, double y) const {
    return x > min_x && x < max_x && y > min_y && y < max_y;
  }
};

class Floor {
 public:
  void AddDitch(const Ditch& d) { ditches_.push_back(d); }
  const std::vector<Ditch>& ditches() const { return ditches_; }
  // The ditch under (x, y), or nullptr where there is ground.
  const Ditch* DitchAt(double x, double y) const {
    for (const Ditch& d : ditches_)
      if (d.Contains(x, y)) return &d;
    return nullptr;
  }
  bool HasGroundAt(double x, double y) const { return DitchAt(x, y) == nullptr; }

  void SetColor(Color c) { color_ = c; }
  // Loads a PNG covering the rectangle [min_x, max_x] x [min_y, max_y].
  // Returns an error message, or an empty string on success.
  std::string LoadImage(const std::string& path, double min_x, double min_y, double max_x,
                        double max_y);
  // An image made by the program (`source` names it in messages), row 0 the
  // max-y edge, stretched over the rectangle as LoadImage's.
  void SetImage(int width, int height, std::vector<Color> pixels, std::string source, double min_x,
                double min_y, double max_x, double max_y) {
    width_ = width;
    height_ = height;
    pixels_ = std::move(pixels);
    path_ = std::move(source);
    min_x_ = min_x;
    min_y_ = min_y;
    max_x_ = max_x;
    max_y_ = max_y;
  }
  // Colour at (x, y); outside the image: the flat colour.
  Color ColorAt(double x, double y) const {
    if (width_ == 0) return color_;
    const double u = (x - min_x_) / (max_x_ - min_x_);
    const double v = (max_y_ - y) / (max_y_ - min_y_);  // image row 0 is the far (max y) edge
    if (u < 0 || u >= 1 || v < 0 || v >= 1) return color_;
    const int px = static_cast<int>(u * width_);
    const int py = static_cast<int>(v * height_);
    return pixels_[static_cast<size_t>(py) * width_ + px];
  }
  double GreyAt(double x, double y) const { return ColorAt(x, y).Grey(); }
  bool has_image() const { return width_ > 0; }
  const std::string& image_path() const { return path_; }

 private:
  Color color_ = Color::White();
  std::string path_;
  int width_ = 0, height_ = 0;
  double min_x_ = 0, min_y_ = 0, max_x_ = 1, max_y_ = 1;
  std::vector<Color> pixels_;
  std::vector<Ditch> ditches_;
};

}  // namespace colony

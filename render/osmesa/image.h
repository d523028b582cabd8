// An RGB image as renderers and cameras produce it, and PNG output.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace colony::render {

// 3 bytes per pixel (r, g, b), rows from the top, pixels from the left.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;

  void Resize(int w, int h) {
    width = w;
    height = h;
    rgb.assign(static_cast<size_t>(w) * h * 3, 0);
  }
  uint8_t* Pixel(int x, int y) { return rgb.data() + (static_cast<size_t>(y) * width + x) * 3; }
};

// Writes `image` as a PNG file, favouring speed over size. Returns an error
// message, or "" on success.
std::string WritePng(const Image& image, const std::string& path);

}  // namespace colony::render

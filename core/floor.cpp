#include "core/floor.h"

#include <png.h>

#include "core/bounds.h"

namespace colony {

std::string Floor::LoadImage(const std::string& path, double min_x, double min_y, double max_x,
                             double max_y) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    return "cannot read PNG image '" + path + "': " + image.message;
  }
  if (static_cast<uint64_t>(image.width) * image.height > kMaxFloorImagePixels) {
    const std::string message =
        "PNG image '" + path + "' is " + std::to_string(image.width) + " x " +
        std::to_string(image.height) + " pixels; accepted: at most " +
        std::to_string(kMaxFloorImagePixels) + " pixels (e.g. 16384 x 16384)";
    png_image_free(&image);
    return message;
  }
  image.format = PNG_FORMAT_RGBA;
  std::vector<Color> pixels(static_cast<size_t>(image.width) * image.height);
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr)) {
    const std::string message = image.message;
    png_image_free(&image);
    return "cannot decode PNG image '" + path + "': " + message;
  }
  width_ = static_cast<int>(image.width);
  height_ = static_cast<int>(image.height);
  pixels_ = std::move(pixels);
  path_ = path;
  min_x_ = min_x;
  min_y_ = min_y;
  max_x_ = max_x;
  max_y_ = max_y;
  return "";
}

}  // namespace colony

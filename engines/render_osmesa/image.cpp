#include "engines/render_osmesa/image.h"

#include <png.h>

namespace colony::render {

std::string WritePng(const Image& image, const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  png.flags = PNG_IMAGE_FLAG_FAST;
  if (!png_image_write_to_file(&png, path.c_str(), 0, image.rgb.data(), 0, nullptr)) {
    return "cannot write PNG file '" + path + "': " + png.message;
  }
  return "";
}

}  // namespace colony::render

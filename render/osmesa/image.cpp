#include "render/osmesa/image.h"

#include <png.h>

#include <vector>

#include "core/error.h"
#include "core/run_files.h"

namespace colony::render {

std::string WritePng(const Image& image, const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  png.flags = PNG_IMAGE_FLAG_FAST;
  // Encoded in memory, then written under a temporary name and renamed: an
  // interrupted run never leaves a truncated frame.
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(png, size, 0, image.rgb.data(), 0, nullptr)) {
    return "cannot encode PNG file '" + path + "': " + png.message;
  }
  std::vector<char> bytes(size);
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.rgb.data(), 0, nullptr)) {
    return "cannot encode PNG file '" + path + "': " + png.message;
  }
  try {
    WriteFileAtomically(path, std::string_view(bytes.data(), size), /*sync=*/false);
  } catch (const RuntimeFailure& e) {
    return e.what();
  }
  return "";
}

}  // namespace colony::render

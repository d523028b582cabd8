// A tiny built-in 5 x 7 bitmap font for labels drawn over frames (robot ids).
#pragma once

#include <string_view>

#include "core/color.h"
#include "render/osmesa/image.h"

namespace colony::render {

// Width in pixels of `text` drawn at `scale`.
int TextWidth(std::string_view text, int scale);
// Draws `text` centred on column `center_x` with its top at row `top`, in
// `color` with a one-pixel dark outline; clipped to the image. Letters,
// digits, spaces and - _ . : / , = + ( ) % are drawn; any other character as '?'.
void DrawText(Image& image, int center_x, int top, std::string_view text, int scale, Color color);

}  // namespace colony::render

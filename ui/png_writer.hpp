// Writing images as PNG files (through Debian's libstb, stb_image_write).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace acdr {

/// Writes an RGB image, top row first, width*height*3 bytes, to `path` as a PNG.
/// Returns false with an error naming the path on failure (bad size, unwritable file).
bool write_png_rgb(const std::string& path, int width, int height,
                   const std::vector<std::uint8_t>& rgb, std::string* error);

/// Converts GL's RGBA read-back (bottom row first) to RGB top row first: the alpha channel is
/// dropped because GL's destination alpha is not the image's opacity (docs/dependencies.md).
std::vector<std::uint8_t> rgba_bottom_up_to_rgb(const std::vector<std::uint8_t>& rgba, int width,
                                                int height);

/// Writes GL's RGBA read-back (bottom row first) as an RGB PNG, flipped upright.
bool write_png_from_gl_rgba(const std::string& path, int width, int height,
                            const std::vector<std::uint8_t>& rgba, std::string* error);

}  // namespace acdr

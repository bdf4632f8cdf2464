// PNG output. libstb.so already holds the stb implementations, so only the declarations are
// included here (no STB_IMAGE_WRITE_IMPLEMENTATION).
#include "ui/png_writer.hpp"

#include <stb_image_write.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace acdr {

bool write_png_rgb(const std::string& path, int width, int height,
                   const std::vector<std::uint8_t>& rgb, std::string* error) {
  const std::size_t expected = static_cast<std::size_t>(std::max(width, 0)) *
                               static_cast<std::size_t>(std::max(height, 0)) * 3;
  if (width <= 0 || height <= 0 || rgb.size() != expected) {
    if (error) {
      *error = path + ": cannot write a " + std::to_string(width) + "x" + std::to_string(height) +
               " PNG from " + std::to_string(rgb.size()) + " bytes (expected " +
               std::to_string(expected) + ", RGB)";
    }
    return false;
  }
  errno = 0;
  if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3)) {
    if (error) {
      *error = path + ": cannot write PNG" +
               (errno ? std::string(" (") + std::strerror(errno) + ")" : std::string());
    }
    return false;
  }
  return true;
}

std::vector<std::uint8_t> rgba_bottom_up_to_rgb(const std::vector<std::uint8_t>& rgba, int width,
                                                int height) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
  if (rgba.size() < static_cast<std::size_t>(width) * height * 4) return {};
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* src = &rgba[static_cast<std::size_t>(height - 1 - y) * width * 4];
    std::uint8_t* dst = &rgb[static_cast<std::size_t>(y) * width * 3];
    for (int x = 0; x < width; ++x) {
      dst[3 * x + 0] = src[4 * x + 0];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 2];
    }
  }
  return rgb;
}

bool write_png_from_gl_rgba(const std::string& path, int width, int height,
                            const std::vector<std::uint8_t>& rgba, std::string* error) {
  return write_png_rgb(path, width, height, rgba_bottom_up_to_rgb(rgba, width, height), error);
}

}  // namespace acdr

// Tests that look at a PNG written by the program: the file as an RGB test::Image (empty when
// it cannot be read).
#pragma once

#include <cstddef>
#include <string>

#include <stb_image.h>

#include "tests/ui/image_probe.hpp"

namespace acdr::test {

inline Image load_png(const std::string& path) {
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
  Image image;
  if (!data) return image;
  image.width = w;
  image.height = h;
  image.rgb.assign(data, data + static_cast<std::size_t>(w) * h * 3);
  stbi_image_free(data);
  return image;
}

}  // namespace acdr::test

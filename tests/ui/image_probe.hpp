// Helpers for tests that look at rendered RGB images (top row first): read a pixel, and count
// the pixels of a window that pass a colour test.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

namespace acdr::test {

struct Rgb {
  int r = 0, g = 0, b = 0;
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< width*height*3, top row first

  Rgb at(int x, int y) const {
    x = std::clamp(x, 0, width - 1);
    y = std::clamp(y, 0, height - 1);
    const std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
  Rgb at(const Eigen::Vector2f& pixel) const {
    return at(static_cast<int>(pixel.x()), static_cast<int>(pixel.y()));
  }

  /// Fraction of the (2*half+1)^2 pixels around `center` for which `test` holds.
  double fraction_in_window(const Eigen::Vector2f& center, int half,
                            const std::function<bool(const Rgb&)>& test) const {
    int hits = 0, total = 0;
    for (int dy = -half; dy <= half; ++dy) {
      for (int dx = -half; dx <= half; ++dx) {
        ++total;
        hits += test(at(static_cast<int>(center.x()) + dx, static_cast<int>(center.y()) + dy));
      }
    }
    return static_cast<double>(hits) / total;
  }

  /// Fraction of all pixels for which `test` holds.
  double fraction(const std::function<bool(const Rgb&)>& test) const {
    std::size_t hits = 0;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) hits += test(at(x, y));
    }
    return static_cast<double>(hits) / (static_cast<double>(width) * height);
  }
};

/// Colour classes of the sample scene (ui/sample_scene.hpp), loose enough for any lighting.
inline bool is_nucleus_yellow(const Rgb& c) {
  return c.r > 90 && c.r >= c.g && c.g > c.b && c.r - c.b > 60;
}
inline bool is_steel(const Rgb& c) {
  const int hi = std::max({c.r, c.g, c.b});
  const int lo = std::min({c.r, c.g, c.b});
  return hi > 110 && hi - lo < 30;
}
inline bool is_wall_blue(const Rgb& c) { return c.b > c.r + 20 && c.b >= c.g; }

}  // namespace acdr::test

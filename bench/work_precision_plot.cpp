// A small rasteriser for the work-precision plot: filled rectangles, lines, markers, and text
// from stb_easy_font's quads.
#include "bench/work_precision_plot.hpp"

#include <stb/stb_easy_font.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace acdr {
namespace {

struct Rgb {
  std::uint8_t r, g, b;
};

class Canvas {
 public:
  Canvas(int w, int h) : w_(w), h_(h), rgb_(std::size_t(w) * h * 3, 255) {}
  void pixel(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    std::uint8_t* p = &rgb_[(std::size_t(y) * w_ + x) * 3];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }
  void rect(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = std::max(0, y0); y < std::min(h_, y1); ++y)
      for (int x = std::max(0, x0); x < std::min(w_, x1); ++x) pixel(x, y, c);
  }
  void line(double x0, double y0, double x1, double y1, Rgb c, int thick = 1, int dash = 0) {
    const double len = std::hypot(x1 - x0, y1 - y0);
    const int n = std::max(1, static_cast<int>(len * 2));
    for (int k = 0; k <= n; ++k) {
      if (dash > 0 && (k / (2 * dash)) % 2 == 1) continue;
      const double t = double(k) / n;
      const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0)));
      const int y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
      rect(x - thick / 2, y - thick / 2, x - thick / 2 + thick, y - thick / 2 + thick, c);
    }
  }
  /// Text at (x, y) (top left), scaled by `scale`, via stb_easy_font's axis-aligned quads.
  void text(double x, double y, const std::string& s, Rgb c, int scale = 2) {
    static char buffer[60000];
    std::string copy = s;
    const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer, sizeof buffer);
    for (int q = 0; q < quads; ++q) {
      const float* v = reinterpret_cast<const float*>(buffer + q * 64);
      // 4 vertices of 16 bytes: x, y, z, colour.
      const float qx0 = v[0], qy0 = v[1], qx1 = v[8], qy1 = v[9];
      rect(static_cast<int>(x + qx0 * scale), static_cast<int>(y + qy0 * scale),
           static_cast<int>(x + qx1 * scale), static_cast<int>(y + qy1 * scale), c);
    }
  }
  int text_width(const std::string& s, int scale = 2) {
    std::string copy = s;
    return stb_easy_font_width(copy.data()) * scale;
  }
  PlotImage take() { return PlotImage{w_, h_, std::move(rgb_)}; }

 private:
  int w_, h_;
  std::vector<std::uint8_t> rgb_;
};

std::string decade_label(int e) {
  char buf[16];
  if (e >= -2 && e <= 3) {
    std::snprintf(buf, sizeof buf, "%g", std::pow(10.0, e));
  } else {
    std::snprintf(buf, sizeof buf, "1e%d", e);
  }
  return buf;
}

}  // namespace

PlotImage plot_work_precision(const BenchReport& report, int width, int height) {
  Canvas c(width, height);
  const Rgb black{20, 20, 20}, grey{215, 215, 215}, dark{120, 120, 120};
  const Rgb ours{31, 119, 180}, peer{214, 39, 40}, mark{44, 160, 44};
  const int left = 110, right = std::max(left + 100, width - 290), top = 80,
            bottom = std::max(top + 100, height - 80);
  constexpr double kFloor = 1e-6;

  // Axis ranges (decades) from the points, including x = 1 and y = 0.05.
  double xmin = 1.0, xmax = 1.0, ymin = 0.05, ymax = 0.05;
  for (const WorkPoint& p : report.points) {
    if (p.is_reference) continue;
    xmin = std::min(xmin, p.wall_s_per_sim_s);
    xmax = std::max(xmax, p.wall_s_per_sim_s);
    ymin = std::min(ymin, std::max(kFloor, p.force_rms_error));
    ymax = std::max(ymax, std::max(kFloor, p.force_rms_error));
  }
  // At least a decade left of real time, so the real-time line stands clear of the axis.
  const int ex0 = std::min(-1, static_cast<int>(std::floor(std::log10(std::max(xmin, 1e-4)))));
  const int ex1 = static_cast<int>(std::ceil(std::log10(std::max(xmax, 1e-4)))) + (xmax == xmin ? 1 : 0);
  const int ey0 = static_cast<int>(std::floor(std::log10(ymin)));
  const int ey1 = std::max(ey0 + 1, static_cast<int>(std::ceil(std::log10(ymax))));
  auto px = [&](double x) {
    return left + (std::log10(std::max(x, 1e-12)) - ex0) / double(ex1 - ex0) * (right - left);
  };
  auto py = [&](double y) {
    return bottom - (std::log10(std::max(y, kFloor)) - ey0) / double(ey1 - ey0) * (bottom - top);
  };

  // Grid and tick labels.
  for (int e = ex0; e <= ex1; ++e) {
    const double x = px(std::pow(10.0, e));
    c.line(x, top, x, bottom, grey);
    const std::string l = decade_label(e);
    c.text(x - c.text_width(l) / 2.0, bottom + 10, l, black);
  }
  for (int e = ey0; e <= ey1; ++e) {
    const double y = py(std::pow(10.0, e));
    c.line(left, y, right, y, grey);
    const std::string l = decade_label(e);
    c.text(left - 12 - c.text_width(l), y - 7, l, black);
  }
  c.line(left, top, left, bottom, black, 2);
  c.line(left, bottom, right, bottom, black, 2);
  // Real time and the 5 % target.
  c.line(px(1.0), top, px(1.0), bottom, mark, 2, 4);
  c.text(px(1.0) + 6, top + 4, "real time", mark);
  c.line(left, py(0.05), right, py(0.05), mark, 2, 4);
  c.text(right - c.text_width("5 % error") - 4, py(0.05) - 20, "5 % error", mark);

  // Points: colour per solver, marker per scene (first scene: square / X, second: diamond /
  // plus, third: triangle / hollow square, further: the same again); the default point ringed.
  std::vector<std::string> scenes;
  for (const WorkPoint& p : report.points)
    if (std::find(scenes.begin(), scenes.end(), p.scene) == scenes.end()) scenes.push_back(p.scene);
  auto scene_index = [&](const std::string& s) {
    return static_cast<int>(std::find(scenes.begin(), scenes.end(), s) - scenes.begin()) % 3;
  };
  auto marker = [&](double x, double y, bool bullet, int shape) {
    if (bullet) {
      if (shape == 0) {
        c.line(x - 6, y - 6, x + 6, y + 6, peer, 3);
        c.line(x - 6, y + 6, x + 6, y - 6, peer, 3);
      } else if (shape == 1) {
        c.line(x - 7, y, x + 7, y, peer, 3);
        c.line(x, y - 7, x, y + 7, peer, 3);
      } else {
        c.line(x - 6, y - 6, x + 6, y - 6, peer, 2);
        c.line(x + 6, y - 6, x + 6, y + 6, peer, 2);
        c.line(x + 6, y + 6, x - 6, y + 6, peer, 2);
        c.line(x - 6, y + 6, x - 6, y - 6, peer, 2);
      }
    } else if (shape == 0) {
      c.rect(static_cast<int>(x) - 5, static_cast<int>(y) - 5, static_cast<int>(x) + 6,
             static_cast<int>(y) + 6, ours);
    } else if (shape == 2) {
      for (int d = -6; d <= 6; ++d) {  // a triangle, apex up
        const int half = (d + 6) / 2 + 1;
        c.rect(static_cast<int>(x) - half, static_cast<int>(y) + d, static_cast<int>(x) + half,
               static_cast<int>(y) + d + 1, ours);
      }
    } else {
      for (int d = -7; d <= 7; ++d) {
        const int half = 7 - std::abs(d);
        c.rect(static_cast<int>(x) - half, static_cast<int>(y) + d, static_cast<int>(x) + half + 1,
               static_cast<int>(y) + d + 1, ours);
      }
    }
  };
  for (const WorkPoint& p : report.points) {
    if (p.is_reference) continue;
    const double x = px(p.wall_s_per_sim_s), y = py(p.force_rms_error);
    marker(x, y, p.solver == "bullet", scene_index(p.scene));
    if (p.is_default) {
      for (int k = 0; k < 48; ++k) {
        const double a = k * 2.0 * M_PI / 48.0;
        const int rx = static_cast<int>(x + 11 * std::cos(a)), ry = static_cast<int>(y + 11 * std::sin(a));
        c.rect(rx - 1, ry - 1, rx + 1, ry + 1, black);
      }
    }
  }

  // Titles and legend.
  c.text(left, 18, "Work-precision: instrument force error vs run time", black, 2);
  const std::string xl = "wall seconds per simulated second";
  c.text((left + right) / 2.0 - c.text_width(xl) / 2.0, bottom + 40, xl, black);
  c.text(12, top - 28, "force RMS error (relative to the converged reference)", black);
  // Legend in the right margin, beside the axes (never over a point).
  const int lx = right + 24, ly = top + 10;

  int row = 0;
  for (std::size_t k = 0; k < scenes.size() && k < 3; ++k) {
    for (bool bullet : {false, true}) {
      bool any = false;
      for (const WorkPoint& p : report.points)
        any = any || (p.scene == scenes[k] && (p.solver == "bullet") == bullet);
      if (!any) continue;
      const double y = ly + 27 * row + 7;
      marker(lx + 6, y, bullet, static_cast<int>(k));
      c.text(lx + 20, y - 7, (bullet ? "Bullet, " : "acdr, ") + scenes[k], black);
      ++row;
    }
  }
  c.text(lx + 20, ly + 27 * row, "ringed: scene defaults", black);
  (void)dark;
  return c.take();
}

}  // namespace acdr

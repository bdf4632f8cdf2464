// A small plot helper on ImGui's draw list (ImGui 1.86 has no plotting beyond PlotLines): line
// series with optional per-point markers, horizontal reference lines (pass line, limits),
// shaded x-intervals (overload, lost input), axes with round tick values, a cursor and a
// hover read-out. Long series are drawn as per-pixel-column min/max envelopes, so a 60 s
// recording at 1 kHz costs a few hundred segments.
#pragma once

#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <imgui.h>

namespace acdr {

struct PlotSeries {
  std::span<const float> x;
  std::span<const float> y;
  ImU32 color = IM_COL32(120, 180, 255, 255);
  std::string label;
  float thickness = 1.5f;
  bool markers = false;                ///< a dot at each point (few points, e.g. attempts)
  std::span<const ImU32> point_colors; ///< per-point marker colours (optional)
};

/// A plain line series.
inline PlotSeries line_series(std::span<const float> x, std::span<const float> y, ImU32 color,
                              std::string label) {
  PlotSeries s;
  s.x = x;
  s.y = y;
  s.color = color;
  s.label = std::move(label);
  return s;
}

/// A horizontal line at `y` (a limit, the pass line).
struct PlotLine {
  float y = 0.0f;
  ImU32 color = IM_COL32(255, 255, 255, 160);
  std::string label;
};

/// A shaded interval of x (e.g. where the shaft was overloaded).
struct PlotBand {
  float x0 = 0.0f, x1 = 0.0f;
  ImU32 color = IM_COL32(255, 160, 0, 60);
};

struct PlotOptions {
  std::string id;            ///< unique within the window
  std::string title;
  ImVec2 size = ImVec2(-1.0f, 180.0f);  ///< -1 width: fill the available width
  float x_min = std::numeric_limits<float>::quiet_NaN();  ///< NaN: from the data
  float x_max = std::numeric_limits<float>::quiet_NaN();
  float y_min = std::numeric_limits<float>::quiet_NaN();
  float y_max = std::numeric_limits<float>::quiet_NaN();
  std::string x_label;
  std::string y_label;
  float cursor_x = std::numeric_limits<float>::quiet_NaN();  ///< a vertical cursor (replay)
  bool integer_x = false;    ///< x ticks at whole numbers (attempt numbers)
};

/// What the user did on the plot this frame.
struct PlotInteraction {
  bool hovered = false;
  bool clicked = false;  ///< left click inside the plot area
  float x_at_mouse = 0.0f;
};

/// Draws the plot at the cursor position and advances the layout.
/// One entry of a legend: a colour chip and what it stands for.
struct LegendItem {
  ImU32 color = 0;
  std::string label;
};

/// A legend laid out as chips with their labels, moving to a new line wherever the next entry
/// would not fit the width left (nothing is cut off). `same_line_as_previous`: start after the
/// last item (e.g. a title) when the first entry fits there.
void draw_legend(std::span<const LegendItem> items, bool same_line_as_previous = false);

PlotInteraction draw_plot(const PlotOptions& options, std::span<const PlotSeries> series,
                          std::span<const PlotLine> lines = {},
                          std::span<const PlotBand> bands = {});

/// "Nice" tick values covering [lo, hi] with about `target` ticks (1, 2, 5 x 10^n steps).
std::vector<float> nice_ticks(float lo, float hi, int target = 5);

}  // namespace acdr

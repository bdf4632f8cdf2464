// Plots on ImGui's draw list.
#include "ui/plot_widgets.hpp"

#include <algorithm>
#include <cstdio>

namespace acdr {

std::vector<float> nice_ticks(float lo, float hi, int target) {
  std::vector<float> ticks;
  if (!(hi > lo) || target < 1) return ticks;
  const double raw = (static_cast<double>(hi) - lo) / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * magnitude;
    if (step >= raw) break;
  }
  const double first = std::ceil(lo / step) * step;
  for (double t = first; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(static_cast<float>(std::abs(t) < 1e-12 * step ? 0.0 : t));
  return ticks;
}

namespace {

std::string tick_text(float v) {
  char text[32];
  const float a = std::abs(v);
  if (a != 0.0f && (a < 1e-3f || a >= 1e5f))
    std::snprintf(text, sizeof text, "%.1e", v);
  else
    std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

void draw_legend(std::span<const LegendItem> items, bool same_line_as_previous) {
  const float chip = 10.0f, gap = 14.0f, inner = 4.0f;
  bool first = !same_line_as_previous;
  for (const LegendItem& item : items) {
    const float need = chip + inner + ImGui::CalcTextSize(item.label.c_str()).x;
    // Beside the previous item when there is room, else on a new line (decided before moving:
    // a SameLine then NewLine would leave the line's end past the pane as content).
    if (!first) {
      const float room = ImGui::GetWindowPos().x + ImGui::GetContentRegionMax().x -
                         ImGui::GetItemRectMax().x - gap;
      if (room >= need) ImGui::SameLine(0, gap);
    }
    first = false;
    ImGui::ColorButton(item.label.c_str(), ImGui::ColorConvertU32ToFloat4(item.color),
                       ImGuiColorEditFlags_NoTooltip, ImVec2(chip, chip));
    ImGui::SameLine(0, inner);
    ImGui::TextUnformatted(item.label.c_str());
  }
}

PlotInteraction draw_plot(const PlotOptions& o, std::span<const PlotSeries> series,
                          std::span<const PlotLine> lines, std::span<const PlotBand> bands) {
  PlotInteraction result;
  ImGui::PushID(o.id.c_str());
  // Title, then the legend as colour chips on the same line.
  if (!o.title.empty()) ImGui::TextUnformatted(o.title.c_str());
  std::vector<LegendItem> legend;
  for (const PlotSeries& s : series)
    if (!s.label.empty()) legend.push_back({s.color, s.label});
  draw_legend(legend, !o.title.empty());

  // Data ranges (NaN limits come from the data and the reference lines).
  float x0 = o.x_min, x1 = o.x_max, y0 = o.y_min, y1 = o.y_max;
  float dx0 = INFINITY, dx1 = -INFINITY, dy0 = INFINITY, dy1 = -INFINITY;
  for (const PlotSeries& s : series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      dx0 = std::min(dx0, s.x[i]);
      dx1 = std::max(dx1, s.x[i]);
      dy0 = std::min(dy0, s.y[i]);
      dy1 = std::max(dy1, s.y[i]);
    }
  }
  for (const PlotLine& l : lines) {
    dy0 = std::min(dy0, l.y);
    dy1 = std::max(dy1, l.y);
  }
  if (std::isnan(x0)) x0 = std::isfinite(dx0) ? dx0 : 0.0f;
  if (std::isnan(x1)) x1 = std::isfinite(dx1) ? dx1 : 1.0f;
  if (std::isnan(y0)) y0 = std::isfinite(dy0) ? std::min(dy0, 0.0f) : 0.0f;
  if (std::isnan(y1)) y1 = std::isfinite(dy1) ? dy1 + 0.08f * (dy1 - y0) : 1.0f;
  if (!(x1 > x0)) x1 = x0 + 1.0f;
  if (!(y1 > y0)) y1 = y0 + 1.0f;

  // Layout: a left margin for y ticks, a bottom margin for x ticks.
  const float width = o.size.x > 0 ? o.size.x : ImGui::GetContentRegionAvail().x;
  const float height = o.size.y;
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float left = 52.0f, bottom = o.x_label.empty() ? 20.0f : 36.0f, top = 6.0f, right = 8.0f;
  const ImVec2 a(origin.x + left, origin.y + top);
  const ImVec2 b(origin.x + width - right, origin.y + height - bottom);
  ImGui::InvisibleButton("plot", ImVec2(width, height));
  result.hovered = ImGui::IsItemHovered();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  auto px = [&](float x) { return a.x + (x - x0) / (x1 - x0) * (b.x - a.x); };
  auto py = [&](float y) { return b.y - (y - y0) / (y1 - y0) * (b.y - a.y); };

  dl->AddRectFilled(a, b, IM_COL32(22, 24, 28, 255));
  dl->PushClipRect(a, b, true);
  for (const PlotBand& band : bands) {
    const float l = std::max(px(band.x0), a.x), r = std::min(px(band.x1), b.x);
    if (r > l) dl->AddRectFilled(ImVec2(l, a.y), ImVec2(std::max(r, l + 1.0f), b.y), band.color);
  }
  // Grid and ticks.
  const ImU32 grid = IM_COL32(255, 255, 255, 22);
  const ImU32 tick_color = IM_COL32(170, 172, 178, 255);
  dl->PopClipRect();
  for (float t : nice_ticks(y0, y1, 4)) {
    dl->AddLine(ImVec2(a.x, py(t)), ImVec2(b.x, py(t)), grid);
    const std::string s = tick_text(t);
    const ImVec2 sz = ImGui::CalcTextSize(s.c_str());
    dl->AddText(ImVec2(a.x - sz.x - 4, py(t) - sz.y * 0.5f), tick_color, s.c_str());
  }
  std::vector<float> xt = nice_ticks(x0, x1, std::max(2, static_cast<int>((b.x - a.x) / 90.0f)));
  if (o.integer_x) {
    xt.erase(std::remove_if(xt.begin(), xt.end(), [](float v) { return v != std::round(v); }),
             xt.end());
  }
  for (float t : xt) {
    dl->AddLine(ImVec2(px(t), a.y), ImVec2(px(t), b.y), grid);
    const std::string s = tick_text(t);
    const ImVec2 sz = ImGui::CalcTextSize(s.c_str());
    dl->AddText(ImVec2(px(t) - sz.x * 0.5f, b.y + 2), tick_color, s.c_str());
  }
  if (!o.x_label.empty()) {
    const ImVec2 sz = ImGui::CalcTextSize(o.x_label.c_str());
    dl->AddText(ImVec2((a.x + b.x - sz.x) * 0.5f, b.y + 18), tick_color, o.x_label.c_str());
  }
  if (!o.y_label.empty()) dl->AddText(ImVec2(a.x + 4, a.y + 2), tick_color, o.y_label.c_str());

  dl->PushClipRect(a, b, true);
  for (const PlotLine& l : lines) {
    dl->AddLine(ImVec2(a.x, py(l.y)), ImVec2(b.x, py(l.y)), l.color, 1.5f);
    if (!l.label.empty()) {
      // Above the line, or below it when there is no room above.
      const ImVec2 sz = ImGui::CalcTextSize(l.label.c_str());
      const float above = py(l.y) - sz.y - 1;
      dl->AddText(ImVec2(b.x - sz.x - 4, above < a.y ? py(l.y) + 1 : above), l.color,
                  l.label.c_str());
    }
  }
  // Series: per pixel column, the min and max of the points in it (an envelope), so dense
  // data keeps its peaks without drawing every point.
  for (const PlotSeries& s : series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    if (n == 0) continue;
    std::vector<ImVec2> path;
    path.reserve(std::min<std::size_t>(n, static_cast<std::size_t>(2 * (b.x - a.x)) + 2));
    int column = -1;
    float lo = 0, hi = 0, last_y = 0;
    auto flush = [&]() {
      if (column < 0) return;
      const float x = a.x + static_cast<float>(column);
      path.emplace_back(x, py(lo));
      if (hi != lo) path.emplace_back(x, py(hi));
      if (last_y != hi) path.emplace_back(x, py(last_y));
    };
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const int c = static_cast<int>(px(s.x[i]) - a.x);
      if (c != column) {
        flush();
        column = c;
        lo = hi = s.y[i];
      }
      lo = std::min(lo, s.y[i]);
      hi = std::max(hi, s.y[i]);
      last_y = s.y[i];
    }
    flush();
    if (path.size() >= 2)
      dl->AddPolyline(path.data(), static_cast<int>(path.size()), s.color, 0, s.thickness);
    if (s.markers) {
      for (std::size_t i = 0; i < n; ++i) {
        const ImU32 c = i < s.point_colors.size() ? s.point_colors[i] : s.color;
        dl->AddCircleFilled(ImVec2(px(s.x[i]), py(s.y[i])), 4.5f, c);
      }
    }
  }
  if (std::isfinite(o.cursor_x))
    dl->AddLine(ImVec2(px(o.cursor_x), a.y), ImVec2(px(o.cursor_x), b.y),
                IM_COL32(255, 255, 255, 200), 1.5f);
  dl->PopClipRect();
  dl->AddRect(a, b, IM_COL32(90, 92, 98, 255));

  // Hover read-out: the nearest point of each series at the pointer's x.
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  if (result.hovered && mouse.x >= a.x && mouse.x <= b.x) {
    result.x_at_mouse = x0 + (mouse.x - a.x) / (b.x - a.x) * (x1 - x0);
    result.clicked = ImGui::IsMouseClicked(0) || ImGui::IsMouseDragging(0);
    ImGui::BeginTooltip();
    ImGui::Text("x = %g", result.x_at_mouse);
    for (const PlotSeries& s : series) {
      const std::size_t n = std::min(s.x.size(), s.y.size());
      if (n == 0) continue;
      const auto it = std::lower_bound(s.x.begin(), s.x.begin() + n, result.x_at_mouse);
      const std::size_t i = std::min<std::size_t>(it - s.x.begin(), n - 1);
      ImGui::Text("%s: %g", s.label.empty() ? "y" : s.label.c_str(), s.y[i]);
    }
    ImGui::EndTooltip();
  }
  ImGui::PopID();
  return result;
}

}  // namespace acdr

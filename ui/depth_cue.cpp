// Depth cues: see depth_cue.hpp.
#include "ui/depth_cue.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "engine/anatomy/anatomy.hpp"
#include "ui/imgui_style.hpp"
#include "ui/render_camera.hpp"
#include "ui/word_wrap.hpp"

namespace acdr {
namespace {

ImU32 color_u32(const ImVec4& c, float alpha = 1.0f) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(c.x, c.y, c.z, c.w * alpha));
}

std::optional<ImVec2> to_screen(const RenderCamera& camera, const ImVec2& display, const Vec3& p) {
  const auto px = project_to_pixel(camera, static_cast<int>(display.x),
                                   static_cast<int>(display.y), p.cast<float>());
  if (!px) return std::nullopt;
  return ImVec2(px->x(), px->y());
}

// A horizontal ring of `radius` around `centre`, projected.
void ring(ImDrawList* dl, const RenderCamera& camera, const ImVec2& display, const Vec3& centre,
          double radius, ImU32 colour, float thickness) {
  constexpr int kSegments = 24;
  ImVec2 points[kSegments];
  for (int i = 0; i < kSegments; ++i) {
    const double a = 2.0 * M_PI * i / kSegments;
    const auto p = to_screen(camera, display,
                             centre + Vec3(radius * std::cos(a), radius * std::sin(a), 0.0));
    if (!p) return;
    points[i] = *p;
  }
  dl->AddPolyline(points, kSegments, colour, ImDrawFlags_Closed, thickness);
}

}  // namespace

DepthReference depth_reference(const World& world, const WorldState& initial) {
  DepthReference r;
  double top = -std::numeric_limits<double>::infinity();
  double bottom = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3f& p : initial.positions) {
    top = std::max(top, static_cast<double>(p.z()));
    bottom = std::min(bottom, static_cast<double>(p.z()));
  }
  if (const Anatomy* anatomy = world.anatomy()) {
    // The disc's front is where its material starts (the vertebral bodies' lips stand
    // further forward); the deepest safe level is the bodies' back wall.
    const SegmentLandmarks& l = anatomy->landmarks();
    r.surface_z_m = initial.positions.empty() ? l.body_front_z_m : top;
    r.floor_z_m = l.body_back_z_m;
    r.valid = r.surface_z_m > r.floor_z_m;
    r.surface_name = "front of the disc";
    r.floor_name = "back of the disc (PLL, spinal cord)";
    return r;
  }
  r.valid = top > bottom;
  r.surface_z_m = top;
  r.floor_z_m = bottom;
  r.surface_name = "top of the material";
  r.floor_name = "bottom of the material";
  return r;
}

DepthCue make_depth_cue(const DepthReference& reference, const Frame& frame) {
  DepthCue cue;
  cue.reference = reference;
  cue.valid = reference.valid;
  cue.tip_m = frame.tip_m;
  cue.depth_m = reference.surface_z_m - frame.tip_m.z();
  cue.to_floor_m = frame.tip_m.z() - reference.floor_z_m;
  return cue;
}

std::string depth_text(const DepthCue& cue) {
  if (!cue.valid) return "";
  char text[200];
  if (cue.depth_m < 0)
    std::snprintf(text, sizeof text, "%.1f mm above the %s", -1e3 * cue.depth_m,
                  cue.reference.surface_name.c_str());
  else if (cue.to_floor_m >= 0)
    std::snprintf(text, sizeof text, "%.1f mm in, %.1f mm to the %s", 1e3 * cue.depth_m,
                  1e3 * cue.to_floor_m, cue.reference.floor_name.c_str());
  else
    std::snprintf(text, sizeof text, "%.1f mm in: %.1f mm beyond the %s", 1e3 * cue.depth_m,
                  -1e3 * cue.to_floor_m, cue.reference.floor_name.c_str());
  return text;
}

void draw_depth_drop_line(const DepthCue& cue, const RenderCamera& camera, const ImVec2& display) {
  if (!cue.valid) return;
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const Vec3 tip = cue.tip_m;
  const Vec3 surface(tip.x(), tip.y(), cue.reference.surface_z_m);
  const Vec3 floor(tip.x(), tip.y(), cue.reference.floor_z_m);
  const auto s_tip = to_screen(camera, display, tip);
  const auto s_surface = to_screen(camera, display, surface);
  const auto s_floor = to_screen(camera, display, floor);
  if (!s_tip || !s_surface || !s_floor) return;
  const bool inside = cue.depth_m >= 0;
  const bool beyond = cue.to_floor_m < 0;
  // The column from the surface to the deepest safe level, faint; the part the tip has
  // travelled (above the surface: the drop to it; below: the way in) bright.
  dl->AddLine(*s_surface, *s_floor, color_u32(ui_colors::kDanger, 0.55f), 1.5f);
  const ImVec4& travel = beyond ? ui_colors::kDanger : inside ? ui_colors::kWarning
                                                               : ui_colors::kInfo;
  dl->AddLine(*s_tip, *s_surface, color_u32(travel), 2.5f);
  ring(dl, camera, display, surface, 1.5e-3, color_u32(ui_colors::kInfo), 2.0f);
  ring(dl, camera, display, floor, 1.5e-3, color_u32(ui_colors::kDanger), 2.0f);
  dl->AddCircleFilled(*s_tip, 4.0f, color_u32(travel));
}

void draw_depth_gauge(const DepthCue& cue, const ImVec2& display) {
  if (!cue.valid) return;
  const float margin = 10.0f;
  const float width = 250.0f;
  ImGui::SetNextWindowPos(ImVec2(display.x - margin, display.y - margin), ImGuiCond_Always,
                          ImVec2(1, 1));
  ImGui::SetNextWindowSize(ImVec2(width, 0));
  ImGui::Begin("Depth of the tip", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize);
  const double span = cue.reference.surface_z_m - cue.reference.floor_z_m;
  // The scale: 5 mm above the surface to 3 mm beyond the deepest safe level, in mm of depth.
  const double top_mm = -5.0, bottom_mm = 1e3 * span + 3.0;
  const float bar_h = 150.0f, bar_w = 26.0f;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  auto y_of = [&](double depth_mm) {
    const double f = std::clamp((depth_mm - top_mm) / (bottom_mm - top_mm), 0.0, 1.0);
    return p0.y + static_cast<float>(f) * bar_h;
  };
  const float x0 = p0.x + 4.0f, x1 = x0 + bar_w;
  dl->AddRectFilled(ImVec2(x0, p0.y), ImVec2(x1, p0.y + bar_h),
                    color_u32(ImVec4(0.16f, 0.17f, 0.20f, 1.0f)), 3.0f);
  // The work between the surface and the deepest safe level, and beyond it.
  dl->AddRectFilled(ImVec2(x0, y_of(0.0)), ImVec2(x1, y_of(1e3 * span)),
                    color_u32(ImVec4(0.55f, 0.50f, 0.42f, 1.0f)));
  dl->AddRectFilled(ImVec2(x0, y_of(1e3 * span)), ImVec2(x1, p0.y + bar_h),
                    color_u32(ui_colors::kDanger, 0.6f));
  const float label_x = x1 + 8.0f;
  const float line_h = ImGui::GetTextLineHeight();
  dl->AddLine(ImVec2(x0 - 3, y_of(0.0)), ImVec2(x1 + 3, y_of(0.0)), color_u32(ui_colors::kInfo), 2);
  dl->AddText(ImVec2(label_x, y_of(0.0) - line_h * 0.5f), color_u32(ui_colors::kInfo),
              "0 mm: front");
  char text[64];
  std::snprintf(text, sizeof text, "%.1f mm: back", 1e3 * span);
  dl->AddLine(ImVec2(x0 - 3, y_of(1e3 * span)), ImVec2(x1 + 3, y_of(1e3 * span)),
              color_u32(ui_colors::kDanger), 2);
  dl->AddText(ImVec2(label_x, y_of(1e3 * span) - line_h * 0.5f), color_u32(ui_colors::kDanger),
              text);
  // The tip: a marker across the bar.
  const double tip_mm = 1e3 * cue.depth_m;
  const float ty = y_of(tip_mm);
  const ImVec4& tip_colour = cue.to_floor_m < 0 ? ui_colors::kDanger
                             : cue.depth_m >= 0 ? ui_colors::kWarning
                                                : ui_colors::kOk;
  dl->AddRectFilled(ImVec2(x0 - 6, ty - 2), ImVec2(x1 + 6, ty + 2), color_u32(tip_colour));
  dl->AddTriangleFilled(ImVec2(x1 + 6, ty), ImVec2(x1 + 14, ty - 6), ImVec2(x1 + 14, ty + 6),
                        color_u32(tip_colour));
  ImGui::Dummy(ImVec2(bar_w + 8, bar_h));
  const float wrap = width - 2 * ImGui::GetStyle().WindowPadding.x;
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + wrap);
  text_colored_wrapped(tip_colour, "%s", depth_text(cue).c_str());
  ImGui::PopTextWrapPos();
  ImGui::End();
}

}  // namespace acdr

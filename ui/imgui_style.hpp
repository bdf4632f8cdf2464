// The look shared by the trainee view and the dashboard: ImGui's dark style with a little more
// air, DejaVu Sans when installed, and the colours the UI uses for states (ok, warning,
// danger) so that every screen speaks the same colour language.
#pragma once

#include <string>

#include <imgui.h>

namespace acdr {

/// Applies the style and loads the font into the *current* ImGui context. Returns the font
/// file used ("" for ImGui's built-in font).
std::string setup_imgui_style(float font_size_px = 16.0f);

/// State colours (RGBA, 0..1).
namespace ui_colors {
inline const ImVec4 kOk{0.35f, 0.78f, 0.42f, 1.0f};       ///< passed, within limits
inline const ImVec4 kMastered{0.16f, 0.60f, 0.28f, 1.0f};  ///< mastered (darker green)
inline const ImVec4 kWarning{0.98f, 0.70f, 0.20f, 1.0f};   ///< approaching a limit
inline const ImVec4 kDanger{0.93f, 0.26f, 0.22f, 1.0f};    ///< over a limit, failed
inline const ImVec4 kLocked{0.38f, 0.39f, 0.42f, 1.0f};    ///< not available yet
inline const ImVec4 kInfo{0.45f, 0.68f, 0.95f, 1.0f};      ///< neutral highlight
inline const ImVec4 kMuted{0.62f, 0.64f, 0.68f, 1.0f};     ///< secondary text
}  // namespace ui_colors

}  // namespace acdr

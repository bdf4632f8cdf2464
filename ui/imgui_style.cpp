// Shared ImGui look.
#include "ui/imgui_style.hpp"

#include <cctype>
#include <fstream>
#include <utility>
#include <vector>

namespace acdr {

std::string setup_imgui_style(float font_size_px) {
  ImGui::StyleColorsDark();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 4.0f;
  style.FrameRounding = 3.0f;
  style.WindowPadding = ImVec2(10, 8);
  style.ItemSpacing = ImVec2(8, 5);
  style.Colors[ImGuiCol_WindowBg].w = 0.90f;

  ImGuiIO& io = ImGui::GetIO();
  const char* kDejaVuSans = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  if (std::ifstream(kDejaVuSans).good() &&
      io.Fonts->AddFontFromFileTTF(kDejaVuSans, font_size_px) != nullptr)
    return kDejaVuSans;
  ImFontConfig config;
  config.SizePixels = font_size_px;
  io.Fonts->AddFontDefault(&config);
  return "";
}

std::string metric_label(const std::string& metric) {
  // Known metrics with hand-written labels; others are derived from the name.
  static const std::vector<std::pair<std::string, std::string>> kLabels = {
      {"nucleus_removed_fraction", "Nucleus removed (fraction)"},
      {"nucleus_removed_mm3", "Nucleus removed (mm³)"},
      {"protected_removed_mm3", "Annulus/endplate removed (mm³)"},
      {"peak_instrument_force_N", "Peak instrument force (N)"},
      {"instrument_force_impulse_Ns", "Instrument force impulse (N·s)"},
      {"peak_contact_force_N", "Peak bone/wall contact force (N)"},
      {"peak_feedback_force_N", "Peak force on the hand (N)"},
      {"peak_bending_moment_Nm", "Peak shaft bending moment (N·m)"},
      {"overload_events", "Shaft overload warnings"},
      {"yield_events", "Shaft yield (bent) events"},
      {"time_over_warning_s", "Time over the overload warning (s)"},
      {"tip_path_length_mm", "Tip path length (mm)"},
      {"duration_s", "Duration (s)"},
      {"idle_time_s", "Idle time (s)"},
  };
  for (const auto& [name, label] : kLabels)
    if (name == metric) return label;
  // snake_case_with_unit -> "Snake case with (unit)"
  std::string words = metric;
  std::string unit;
  static const char* kUnits[] = {"_mm3", "_mm", "_Ns", "_Nm", "_N", "_s", "_m"};
  for (const char* u : kUnits) {
    const std::string suffix = u;
    if (words.size() > suffix.size() &&
        words.compare(words.size() - suffix.size(), suffix.size(), suffix) == 0) {
      unit = suffix.substr(1);
      words.resize(words.size() - suffix.size());
      break;
    }
  }
  for (char& c : words)
    if (c == '_') c = ' ';
  if (!words.empty()) words[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(words[0])));
  return unit.empty() ? words : words + " (" + unit + ")";
}

}  // namespace acdr

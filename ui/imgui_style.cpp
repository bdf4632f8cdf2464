// Shared ImGui look.
#include "ui/imgui_style.hpp"

#include <fstream>

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

}  // namespace acdr

// Text wrapped at spaces (see the header): lines measured with the current font, each drawn
// unwrapped.
#include "ui/word_wrap.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <string>

#include <imgui_internal.h>

namespace acdr {

std::vector<std::string_view> wrap_at_spaces(std::string_view text, float width,
                                             const std::function<float(std::string_view)>& measure) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t feed = text.find('\n', start);
    const std::string_view para =
        text.substr(start, feed == std::string_view::npos ? std::string_view::npos : feed - start);
    // One paragraph: grow each line word by word while it fits.
    std::size_t line_begin = 0;
    while (true) {
      std::size_t line_end = para.find(' ', line_begin);  // at least the first word
      if (line_end == std::string_view::npos) line_end = para.size();
      while (line_end < para.size()) {
        std::size_t next = para.find(' ', line_end + 1);
        if (next == std::string_view::npos) next = para.size();
        if (measure(para.substr(line_begin, next - line_begin)) > width) break;
        line_end = next;
      }
      lines.push_back(para.substr(line_begin, line_end - line_begin));
      if (line_end >= para.size()) break;
      line_begin = line_end + 1;  // the space at the break is dropped
    }
    if (feed == std::string_view::npos) break;
    start = feed + 1;
  }
  return lines;
}

namespace {

void draw_wrapped(const char* fmt, va_list args) {
  char stack[1024];
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(stack, sizeof stack, fmt, copy);
  va_end(copy);
  std::string heap;
  std::string_view text(stack, n < 0 ? 0 : std::min<std::size_t>(static_cast<std::size_t>(n), sizeof stack - 1));
  if (n >= static_cast<int>(sizeof stack)) {
    heap.resize(static_cast<std::size_t>(n) + 1);
    std::vsnprintf(heap.data(), heap.size(), fmt, args);
    heap.resize(static_cast<std::size_t>(n));
    text = heap;
  }
  // The width TextWrapped would wrap at: the pushed wrap position, else the region's edge.
  ImGuiWindow* window = ImGui::GetCurrentWindow();
  const float wrap_pos = window->DC.TextWrapPos < 0.0f ? 0.0f : window->DC.TextWrapPos;
  const float width = ImGui::CalcWrapWidthForPos(window->DC.CursorPos, wrap_pos);
  const auto measure = [](std::string_view s) {
    return ImGui::CalcTextSize(s.data(), s.data() + s.size()).x;
  };
  // One block, as TextWrapped draws it: after SameLine every line starts where the first did.
  std::string block;
  block.reserve(text.size() + 8);
  const std::vector<std::string_view> lines = wrap_at_spaces(text, width, measure);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i > 0) block += '\n';
    block.append(lines[i]);
  }
  ImGui::PushTextWrapPos(-1.0f);  // the lines are already broken
  ImGui::TextUnformatted(block.data(), block.data() + block.size());
  ImGui::PopTextWrapPos();
}

}  // namespace

void text_wrapped(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  draw_wrapped(fmt, args);
  va_end(args);
}

void text_colored_wrapped(const ImVec4& color, const char* fmt, ...) {
  ImGui::PushStyleColor(ImGuiCol_Text, color);
  va_list args;
  va_start(args, fmt);
  draw_wrapped(fmt, args);
  va_end(args);
  ImGui::PopStyleColor();
}

}  // namespace acdr

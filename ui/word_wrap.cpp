// Text wrapped at spaces (see the header): lines measured with the current font, each drawn
// unwrapped.
#include "ui/word_wrap.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <utility>

#include <imgui_internal.h>

namespace acdr {

namespace {

// Where a line of `para` (no line feeds) may end at or after `from`: before a space (dropped)
// or after one of `break_after` (kept); as (end of this piece, start of the next).
std::pair<std::size_t, std::size_t> next_break(std::string_view para, std::size_t from,
                                               std::string_view break_after) {
  for (std::size_t k = from; k < para.size(); ++k) {
    if (para[k] == ' ') return {k, k + 1};
    if (k + 1 < para.size() && break_after.find(para[k]) != std::string_view::npos)
      return {k + 1, k + 1};
  }
  return {para.size(), para.size()};
}

// The paragraphs of `text` (its lines between line feeds; one empty one for empty text).
std::vector<std::string_view> paragraphs(std::string_view text) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t feed = text.find('\n', start);
    if (feed == std::string_view::npos) {
      out.push_back(text.substr(start));
      return out;
    }
    out.push_back(text.substr(start, feed - start));
    start = feed + 1;
  }
}

}  // namespace

std::vector<std::string_view> wrap_at_spaces(std::string_view text, float width,
                                             const std::function<float(std::string_view)>& measure,
                                             std::string_view break_after) {
  std::vector<std::string_view> lines;
  for (const std::string_view para : paragraphs(text)) {
    // One paragraph: each line takes at least one piece, then more while they fit.
    std::size_t line_begin = 0;
    while (true) {
      auto [end, next] = next_break(para, line_begin, break_after);
      if (measure(para.substr(line_begin, end - line_begin)) > width) {
        // A piece wider than the line: as much of it as fits (at least one character, never
        // inside a UTF-8 sequence), the rest on the next line.
        std::size_t cut = line_begin + 1;
        while (cut < end && (static_cast<unsigned char>(para[cut]) & 0xC0) == 0x80) ++cut;
        for (std::size_t k = cut + 1; k < end; ++k) {
          if ((static_cast<unsigned char>(para[k]) & 0xC0) == 0x80) continue;
          if (measure(para.substr(line_begin, k - line_begin)) > width) break;
          cut = k;
        }
        if (cut < end) {
          lines.push_back(para.substr(line_begin, cut - line_begin));
          line_begin = cut;
          continue;
        }
      }
      while (end < para.size()) {
        const auto [end2, next2] = next_break(para, next, break_after);
        if (measure(para.substr(line_begin, end2 - line_begin)) > width) break;
        end = end2;
        next = next2;
      }
      lines.push_back(para.substr(line_begin, end - line_begin));
      if (end >= para.size()) break;
      line_begin = next;
    }
  }
  return lines;
}

float widest_piece(std::string_view text, const std::function<float(std::string_view)>& measure,
                   std::string_view break_after) {
  float widest = 0.0f;
  for (const std::string_view para : paragraphs(text)) {
    for (std::size_t begin = 0; begin < para.size();) {
      const auto [end, next] = next_break(para, begin, break_after);
      widest = std::max(widest, measure(para.substr(begin, end - begin)));
      begin = next;
    }
  }
  return widest;
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
  wrapped_label(text);
}

}  // namespace

void wrapped_label(std::string_view text, std::string_view break_after) {
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
  const std::vector<std::string_view> lines = wrap_at_spaces(text, width, measure, break_after);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i > 0) block += '\n';
    block.append(lines[i]);
  }
  ImGui::PushTextWrapPos(-1.0f);  // the lines are already broken
  ImGui::TextUnformatted(block.data(), block.data() + block.size());
  ImGui::PopTextWrapPos();
}

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

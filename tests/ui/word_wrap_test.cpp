// Text wrapped at spaces only: a number is never split at its decimal point, as Dear ImGui's
// own wrapping splits it (after '.'), measured in the real ImGui font too.
#include "ui/word_wrap.hpp"

#include <gtest/gtest.h>

#include <string>

#include "ui/imgui_offscreen.hpp"

namespace acdr {
namespace {

// Every character 1 unit wide.
float chars(std::string_view s) { return static_cast<float>(s.size()); }

TEST(WordWrap, BreaksAtSpacesOnlyAndKeepsNumbersWhole) {
  const auto lines = wrap_at_spaces("moment 0.438 N.m against 0.08", 10.0f, chars);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "moment");
  EXPECT_EQ(lines[1], "0.438 N.m");
  EXPECT_EQ(lines[2], "against");
  EXPECT_EQ(lines[3], "0.08");
  for (auto l : lines) EXPECT_LE(chars(l), 10.0f) << l;
}

TEST(WordWrap, LineFeedsLongWordsAndEmptyText) {
  const auto lines = wrap_at_spaces("a b\nunbreakable c", 5.0f, chars);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "a b");
  EXPECT_EQ(lines[1], "unbre");  // wider than the line by itself: cut where the width ends
  EXPECT_EQ(lines[2], "akabl");
  EXPECT_EQ(lines[3], "e c");
  EXPECT_EQ(wrap_at_spaces("", 5.0f, chars).size(), 1u);
  EXPECT_EQ(wrap_at_spaces("fits", 5.0f, chars).size(), 1u);
  const auto blank = wrap_at_spaces("x\n\ny", 5.0f, chars);
  ASSERT_EQ(blank.size(), 3u);
  EXPECT_EQ(blank[1], "");
}

TEST(WordWrap, IdentifiersBreakAfterTheirHyphens) {
  const auto lines = wrap_at_spaces("4. c4c5-full-discectomy", 10.0f, chars, "-");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "4. c4c5-");
  EXPECT_EQ(lines[1], "full-");
  EXPECT_EQ(lines[2], "discectomy");
  // Without the hyphen rule the id is one piece, cut where the width ends.
  EXPECT_EQ(wrap_at_spaces("4. c4c5-full-discectomy", 10.0f, chars)[1], "c4c5-full-");
  // A hyphen before a space gives one break, not an empty line.
  EXPECT_EQ(wrap_at_spaces("a- b", 2.0f, chars, "-").size(), 2u);
}

TEST(WordWrap, TheWidestPieceIsTheNarrowestLineThatCutsNoWord) {
  EXPECT_EQ(widest_piece("3. c4c5-degenerated", chars, "-"), 11.0f);  // "degenerated"
  EXPECT_EQ(widest_piece("3. c4c5-degenerated", chars), 16.0f);       // "c4c5-degenerated"
  EXPECT_EQ(widest_piece("a\nlonger b", chars), 6.0f);
  EXPECT_EQ(widest_piece("", chars), 0.0f);
  // At that width nothing is cut; one unit less, the widest piece is.
  const std::string text = "4. c4c5-full-discectomy";
  const float w = widest_piece(text, chars, "-");
  for (auto line : wrap_at_spaces(text, w, chars, "-")) EXPECT_NE(line, "discectom");
  bool cut = false;
  for (auto line : wrap_at_spaces(text, w - 1.0f, chars, "-")) cut |= line == "discectom";
  EXPECT_TRUE(cut);
}

TEST(WordWrap, InTheImGuiFontANumberIsNotSplitWhereImGuiWouldSplitIt) {
  std::string error;
  auto ui = ImGuiOffscreen::create(640, 200, &error);
  ASSERT_TRUE(ui) << error;
  const std::string text = "Peak shaft bending moment 0.438 against the experts' 0.08";
  const std::string head = "Peak shaft bending moment 0.";
  std::string imgui_first_line;
  std::vector<std::string> ours;
  float block_height = 0.0f, line_height = 0.0f;
  const auto draw = [&] {
    // A width that ends inside "0.438".
    const float width = ImGui::CalcTextSize(head.c_str()).x + 1.0f;
    const char* imgui_break =
        ImGui::GetFont()->CalcWordWrapPositionA(1.0f, text.c_str(), text.c_str() + text.size(), width);
    imgui_first_line.assign(text.c_str(), imgui_break);
    ours.clear();
    for (auto l : wrap_at_spaces(text, width, [](std::string_view s) {
           return ImGui::CalcTextSize(s.data(), s.data() + s.size()).x;
         })) {
      ours.emplace_back(l);
    }
    // Drawn in a window that narrow: as many lines as wrap_at_spaces gave.
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(width + 2.0f * ImGui::GetStyle().WindowPadding.x, 0));
    ImGui::Begin("wrap", nullptr, ImGuiWindowFlags_NoDecoration);
    const float y0 = ImGui::GetCursorPosY();
    text_wrapped("%s", text.c_str());
    block_height = ImGui::GetCursorPosY() - y0 - ImGui::GetStyle().ItemSpacing.y;
    line_height = ImGui::GetTextLineHeight();
    ImGui::End();
  };
  std::vector<std::uint8_t> rgb;
  ASSERT_TRUE(ui->render(nullptr, draw, &rgb, &error)) << error;
  EXPECT_EQ(imgui_first_line, head) << "ImGui's own wrap no longer breaks after '.'";
  ASSERT_GE(ours.size(), 2u);
  EXPECT_EQ(ours[0], "Peak shaft bending moment");
  EXPECT_EQ(ours[1].substr(0, 5), "0.438");
  EXPECT_NEAR(block_height, ours.size() * line_height, 0.5f * line_height);
}

}  // namespace
}  // namespace acdr

// Wrapped text that breaks lines at spaces only. Dear ImGui's own wrapping (TextWrapped, or
// Text under PushTextWrapPos) also breaks after '.', ',', ';', '!', '?' and '"', so a number
// such as 0.438 could end one line with "0." and start the next with "438": a trainee reading
// a score reason, an alert or a force would misread it. These draw the same text broken only
// at spaces and line feeds.
#pragma once

#include <functional>
#include <string_view>
#include <vector>

#include <imgui.h>

namespace acdr {

/// Lines of `text` no wider than `width` by `measure`, broken at spaces (dropped at the break),
/// after any character of `break_after` (kept: "c4c5-" / "healthy") and at line feeds; only a
/// piece wider than `width` by itself is cut where the width ends.
std::vector<std::string_view> wrap_at_spaces(std::string_view text, float width,
                                             const std::function<float(std::string_view)>& measure,
                                             std::string_view break_after = {});

/// The width by `measure` of the widest piece of `text` that wrap_at_spaces never breaks (between
/// spaces, line feeds and the characters of `break_after`): the narrowest line that shows
/// `text` without cutting a word.
float widest_piece(std::string_view text, const std::function<float(std::string_view)>& measure,
                   std::string_view break_after = {});

/// `text` as is (no formatting), wrapped like text_wrapped, also breaking after any character
/// of `break_after` (e.g. "-" for identifiers such as module ids).
void wrapped_label(std::string_view text, std::string_view break_after = {});

/// ImGui::TextWrapped's replacement: printf-style text wrapped at spaces at the current text
/// wrap position (PushTextWrapPos), or the content region's right edge when none is set.
void text_wrapped(const char* fmt, ...) IM_FMTARGS(1);
/// The same in a colour.
void text_colored_wrapped(const ImVec4& color, const char* fmt, ...) IM_FMTARGS(2);

}  // namespace acdr

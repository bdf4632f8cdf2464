// A rubric written back as the "rubric" object of a scenario file, in the bundled modules'
// layout (one line per gate, one block per term), and put in place of a file's own rubric
// without touching the rest of its text (acdr calibrate --write).
#pragma once

#include <string>
#include <string_view>

#include "assessment/rubric.hpp"

namespace acdr {

/// The JSON text of `rubric` as an object, its inner lines indented by `indent` + 2 spaces and
/// its closing brace by `indent` (the opening brace has none: it follows a key).
std::string rubric_fragment(const Rubric& rubric, int indent = 2);

/// `text` (a scenario file) with the value of its top-level "rubric" key replaced by
/// rubric_fragment(rubric, the key's indentation). False with `error` set (naming the line)
/// when the file has no top-level "rubric" object.
bool replace_rubric(std::string& text, const Rubric& rubric, std::string* error);

}  // namespace acdr

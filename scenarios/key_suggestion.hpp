// "Did you mean ...": the nearest known key to a misspelt one, so a typo in a scenario file is
// both caught and easy to fix.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace acdr {

/// Edit distance (insertions, deletions, substitutions, adjacent swaps), ignoring ASCII case.
/// Inputs longer than 256 bytes are compared by their first 256 bytes (bounded cost).
int edit_distance(std::string_view a, std::string_view b);

/// The known key closest to `typed`, or nothing when none is close enough to be a plausible
/// typo. A key without its unit suffix ("spacing") matches the suffixed key ("spacing_mm").
std::optional<std::string> nearest_key(std::string_view typed, const std::vector<std::string>& known);

}  // namespace acdr

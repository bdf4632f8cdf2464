// `acdr validate FILE...`: checks scenario files and prints every problem, one per line, in the
// `file:line: /json/path: what is wrong (got X, expected Y)` form, or `OK file` for a good one.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace acdr {

/// Validates each file in order. Returns 0 when every file is valid, 1 when any has an error,
/// 2 when no file was given. Never throws for bad input.
int run_validate(const std::vector<std::string>& files, std::ostream& out);

}  // namespace acdr

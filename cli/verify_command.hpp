// `acdr verify [CASE.json...] [--json] [--fast]`: analytic verification of the nucleus physics.
// Runs the built-in cases (or the cases of the given files), prints a table of simulated vs
// analytic values or the JSON {"cases": [...], "passed": bool}, and fails on any miss.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace acdr {

struct VerifyOptions {
  std::vector<std::string> case_files;  ///< empty: the built-in cases
  bool json = false;                    ///< JSON on stdout instead of the table
  bool fast = false;                    ///< the smaller ctest scenes (same tolerances)
};

/// Returns 0 when every row passes, 1 when any fails, 2 when a case file is invalid (its errors
/// go to `err`, one per line).
int run_verify(const VerifyOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr

// Author case files for `acdr verify CASE.json`: which built-in verification case to run and
// with which parameters (material, geometry, step), so an author can check that the physics
// holds for their own material. Format (docs/verification.md):
//   {"cases": [{"case": "couette_shear", "name": "stiff gel",
//               "parameters": {"viscosity_Pa_s": 1000, "gap_m": 0.005}}]}
// A single case object at the root is accepted too. Parameters are SI numbers named with their
// unit; unknown cases or parameters are errors naming the file, line, JSON path, the value and
// what was expected.
#pragma once

#include <string>
#include <vector>

#include "verification/verification_case.hpp"
#include "scenarios/scenario_error.hpp"

namespace acdr {

struct VerificationCaseFile {
  std::vector<VerificationCaseSpec> cases;
  std::vector<ScenarioError> errors;
  bool ok() const { return errors.empty(); }
};

/// Parses case-file text; `path` names the file in messages. `fast` starts each case from the
/// fast (ctest) defaults before the file's parameters are applied.
VerificationCaseFile parse_verification_case_file(const std::string& text,
                                                  const std::string& path, bool fast = false);

/// Reads and parses a case file (an unreadable file is one error).
VerificationCaseFile load_verification_case_file(const std::string& path, bool fast = false);

}  // namespace acdr

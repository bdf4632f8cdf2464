// Analytic verification of the nucleus physics (`acdr verify`): each case builds a
// small scene from plain parameters, simulates it and compares one or more quantities with
// their closed form (seed Eq. 2-11 and textbook results). Parameters are named numbers in SI
// units so author case files (scenarios/verification_case_file) can override any of them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace acdr {

/// One named parameter of a case: SI value, unit and meaning (for docs and error messages).
struct CaseParameter {
  std::string name;
  double value = 0.0;
  std::string unit;
  std::string doc;
};

/// A case to run: which built-in case and its parameters (defaults filled in).
struct VerificationCaseSpec {
  std::string name;        ///< row label; defaults to the kind
  std::string kind;        ///< one of verification_case_kinds()
  std::vector<CaseParameter> params;

  /// Value of a parameter (asserts it exists: the kinds' defaults declare every name).
  double get(std::string_view param) const;
  /// Sets an existing parameter; false if the kind has no such parameter.
  bool set(std::string_view param, double value);
};

/// One compared quantity.
struct VerificationRow {
  std::string case_name;
  std::string quantity;
  double simulated = 0.0;
  double analytic = 0.0;
  double rel_error = 0.0;
  double tolerance = 0.0;
  bool passed = false;
  std::string note;  ///< what went wrong (NaN, solver trouble) or how it was measured
};

/// The built-in case kinds, in the order `acdr verify` runs them.
std::vector<std::string> verification_case_kinds();

/// The default spec of a kind (empty kind string if unknown). `fast` picks smaller scenes and
/// shorter runs for ctest; the same physics and tolerances.
VerificationCaseSpec default_verification_case(std::string_view kind, bool fast = false);

/// Runs a case: simulates and compares. Never throws on physics trouble: a NaN or a failed
/// solve is a failed row with a note.
std::vector<VerificationRow> run_verification_case(const VerificationCaseSpec& spec);

/// Runs every built-in case with its defaults.
std::vector<VerificationRow> run_builtin_verification(bool fast = false);

/// Relative error |sim - ana| / |ana| (absolute error when ana == 0).
double relative_error(double simulated, double analytic);

}  // namespace acdr

// Internal to verification/: the finite-element cases of the bone (one file each), beside the
// nucleus cases in cases.hpp.
#pragma once

#include <vector>

#include "verification/verification_case.hpp"

namespace acdr::verification {

VerificationCaseSpec bone_compression_defaults(bool fast);
std::vector<VerificationRow> run_bone_compression(const VerificationCaseSpec& spec);
VerificationCaseSpec bone_cantilever_defaults(bool fast);
std::vector<VerificationRow> run_bone_cantilever(const VerificationCaseSpec& spec);
VerificationCaseSpec bone_convergence_defaults(bool fast);
std::vector<VerificationRow> run_bone_convergence(const VerificationCaseSpec& spec);

}  // namespace acdr::verification

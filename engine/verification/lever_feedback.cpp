// lever_feedback: placeholder being written.
#include "engine/verification/cases.hpp"
namespace acdr::verification {
VerificationCaseSpec lever_feedback_defaults(bool fast) { VerificationCaseSpec s; add_material_parameters(s, 1e-3); s.params.push_back({"tolerance", 0.05, "1", ""}); return s; }
std::vector<VerificationRow> run_lever_feedback(const VerificationCaseSpec& spec) { VerificationRow r; r.case_name = spec.name; fail_row(r, "not written"); return {r}; }
}

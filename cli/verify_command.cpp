// The body of `acdr verify`: load case files (if any), run, print the table or JSON.
#include "cli/verify_command.hpp"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "scenarios/verification_case_file.hpp"
#include "verification/verification_case.hpp"

namespace acdr {
namespace {

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

void print_table(const std::vector<VerificationRow>& rows, std::ostream& out) {
  char line[512];
  std::snprintf(line, sizeof line, "%-20s %-40s %13s %13s %9s %9s  %s\n", "case", "quantity",
                "simulated", "analytic", "rel_error", "tolerance", "passed");
  out << line;
  for (const auto& r : rows) {
    std::snprintf(line, sizeof line, "%-20s %-40s %13s %13s %9.4f %9.4f  %s", r.case_name.c_str(),
                  r.quantity.c_str(), number(r.simulated).c_str(), number(r.analytic).c_str(),
                  r.rel_error, r.tolerance, r.passed ? "yes" : "NO");
    out << line;
    if (!r.note.empty()) out << "  (" << r.note << ")";
    out << '\n';
  }
}

}  // namespace

int run_verify(const VerifyOptions& options, std::ostream& out, std::ostream& err) {
  std::vector<VerificationCaseSpec> specs;
  if (options.case_files.empty()) {
    for (const auto& kind : verification_case_kinds())
      specs.push_back(default_verification_case(kind, options.fast));
  } else {
    bool bad = false;
    for (const auto& path : options.case_files) {
      VerificationCaseFile file = load_verification_case_file(path, options.fast);
      for (const auto& e : file.errors) err << e.to_string() << '\n';
      bad = bad || !file.ok();
      specs.insert(specs.end(), file.cases.begin(), file.cases.end());
    }
    if (bad) return 2;
  }

  std::vector<VerificationRow> rows;
  for (const auto& spec : specs) {
    auto r = run_verification_case(spec);
    rows.insert(rows.end(), r.begin(), r.end());
  }
  bool passed = !rows.empty();
  for (const auto& r : rows) passed = passed && r.passed;

  if (options.json) {
    nlohmann::json doc;
    doc["cases"] = nlohmann::json::array();
    for (const auto& r : rows) {
      nlohmann::json c = {{"name", r.case_name},      {"quantity", r.quantity},
                          {"simulated", r.simulated}, {"analytic", r.analytic},
                          {"rel_error", r.rel_error}, {"tolerance", r.tolerance},
                          {"passed", r.passed}};
      if (!r.note.empty()) c["note"] = r.note;
      doc["cases"].push_back(c);
    }
    doc["passed"] = passed;
    out << doc.dump(2) << '\n';
  } else {
    print_table(rows, out);
    std::size_t failed = 0;
    for (const auto& r : rows) failed += r.passed ? 0 : 1;
    out << (passed ? "all " + std::to_string(rows.size()) + " checks passed"
                   : std::to_string(failed) + " of " + std::to_string(rows.size()) +
                         " checks FAILED")
        << '\n';
  }
  return passed ? 0 : 1;
}

}  // namespace acdr

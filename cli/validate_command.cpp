// The body of `acdr validate`: the loader does the work; this prints its verdict per file, and
// for a valid file what it will cost to run.
#include "cli/validate_command.hpp"

#include "scenarios/scenario_cost.hpp"
#include "scenarios/scenario_loader.hpp"

namespace acdr {

int run_validate(const std::vector<std::string>& files, std::ostream& out) {
  if (files.empty()) {
    out << "acdr validate: no files given (expected one or more scenario files)\n";
    return 2;
  }
  int failed = 0;
  for (const std::string& path : files) {
    const LoadResult result = load_scenario_file(path);
    if (result.ok()) {
      out << "OK " << path << " (" << cost_summary(estimate_cost(*result.model)) << ")\n";
      continue;
    }
    ++failed;
    for (const ScenarioError& e : result.errors) out << e.to_string() << '\n';
  }
  if (files.size() > 1) {
    out << (files.size() - static_cast<std::size_t>(failed)) << " of " << files.size()
        << " files valid\n";
  }
  return failed == 0 ? 0 : 1;
}

}  // namespace acdr

// `acdr calibrate`: gathers the cohort (app/expert_cohort.hpp), calibrates, prints or writes.
#include "cli/calibrate_command.hpp"

#include <cstdio>
#include <fstream>
#include <ostream>
#include <sstream>

#include "app/expert_cohort.hpp"
#include "assessment/calibration.hpp"
#include "scenarios/rubric_fragment.hpp"
#include "scenarios/scenario_loader.hpp"

namespace acdr {

int run_calibrate(const CalibrateOptions& options, std::ostream& out, std::ostream& err) {
  const LoadResult loaded = load_scenario_file(options.scenario);
  if (!loaded.ok()) {
    err << to_string(loaded.errors);
    return 2;
  }
  const ScenarioModel& scenario = *loaded.model;
  std::string error;
  std::optional<std::vector<CohortAttempt>> cohort;
  if (!options.demonstrations.empty()) {
    auto files = expert_demonstrations(options.demonstrations, &error);
    if (files) {
      cohort = cohort_from_trajectories(scenario, *files, &error, [&](const std::string& f) {
        err << "replaying " << f << "\n";
      });
    }
  } else {
    cohort.emplace();
    for (const std::string& record : options.records) {
      auto part = cohort_from_record(record, scenario.id, options.trainees, &error);
      if (!part) {
        cohort.reset();
        break;
      }
      for (CohortAttempt& a : *part) {
        if (options.records.size() > 1) a.label = record + ": " + a.label;
        cohort->push_back(std::move(a));
      }
    }
  }
  if (!cohort) {
    err << error << "\n";
    return 2;
  }
  std::vector<Metrics> experts;
  for (const CohortAttempt& a : *cohort) experts.push_back(a.metrics);
  CalibrationMethod method;
  method.trim_fraction = options.trim_fraction;
  method.pass_sds = options.pass_sds;
  method.task_share = options.task_share;
  const auto calibration = calibrate(scenario.rubric, experts, method, &error);
  if (!calibration) {
    err << options.scenario << ": " << error << "\n";
    return 2;
  }
  out << "module " << scenario.id << ": " << cohort->size() << " expert attempt(s)\n";
  for (const CohortAttempt& a : *cohort) out << "  " << a.label << "\n";
  out << calibration_table(scenario.rubric, *calibration);
  const Rubric rubric = apply_calibration(scenario.rubric, *calibration);
  if (options.leave_one_out) {
    const auto loo = leave_one_out(scenario.rubric, experts, method, &error);
    if (!loo) {
      err << options.scenario << ": " << error << "\n";
      return 2;
    }
    out << "leave-one-out (each expert against the others' benchmarks):\n";
    for (const LeaveOneOut& l : *loo) {
      char line[200];
      std::snprintf(line, sizeof line, "  %-28s %5.1f %s\n", (*cohort)[l.expert].label.c_str(),
                    l.score.score, l.score.passed ? "passed" : "not passed");
      out << line;
      for (const std::string& r : l.score.reasons) out << "      " << r << "\n";
    }
  }
  const std::string fragment = "\"rubric\": " + rubric_fragment(rubric, 0) + "\n";
  if (!options.out.empty()) {
    std::ofstream f(options.out, std::ios::binary);
    f << fragment;
    if (!f) {
      err << options.out << ": cannot write the rubric fragment\n";
      return 2;
    }
  }
  if (options.write) {
    std::ifstream in(options.scenario, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    if (!replace_rubric(s, rubric, &error)) {
      err << options.scenario << ": " << error << "\n";
      return 2;
    }
    // Only a file that still loads is written back.
    const LoadResult check = load_scenario_text(s, options.scenario);
    if (!check.ok()) {
      err << to_string(check.errors);
      return 2;
    }
    std::ofstream f(options.scenario, std::ios::binary | std::ios::trunc);
    f << s;
    if (!f) {
      err << options.scenario << ": cannot write the calibrated rubric\n";
      return 2;
    }
    out << "wrote the calibrated rubric into " << options.scenario << "\n";
  } else {
    out << fragment;
  }
  return 0;
}

}  // namespace acdr

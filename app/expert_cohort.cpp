// Gathering an expert cohort and reporting its benchmarks.
#include "app/expert_cohort.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "app/attempt_runner.hpp"
#include "db/attempt_store.hpp"
#include "engine/world/world.hpp"

namespace acdr {

std::optional<std::vector<CohortAttempt>> cohort_from_record(const std::string& db_path,
                                                             const std::string& module_id,
                                                             const std::vector<std::string>& trainees,
                                                             std::string* error) {
  OpenOptions open;
  open.create = false;
  auto db = open_store(db_path, open, nullptr);
  if (!db) {
    *error = db.error().message;
    return std::nullopt;
  }
  AttemptFilter filter;
  filter.module_id = module_id;
  auto rows = list_attempts(db.value(), filter, {true, false, false});
  if (!rows) {
    *error = rows.error().message;
    return std::nullopt;
  }
  std::vector<CohortAttempt> out;
  for (const AttemptRecord& row : rows.value()) {
    if (row.status != AttemptStatus::kCompleted) continue;
    if (!trainees.empty() &&
        (!row.trainee_id ||
         std::find(trainees.begin(), trainees.end(), *row.trainee_id) == trainees.end()))
      continue;
    out.push_back({"attempt " + std::to_string(row.id) + " (" +
                       (row.trainee_id ? *row.trainee_id : std::string("practice")) + ")",
                   row.metrics});
  }
  return out;
}

std::optional<std::vector<std::string>> expert_demonstrations(const std::string& dir,
                                                              std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::string> files;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind("expert_", 0) == 0 && it->path().extension() == ".csv" &&
        name.find('.') == name.size() - 4)  // expert_3.csv, not expert_3.cup.csv
      files.push_back(it->path().string());
  }
  if (ec) {
    *error = dir + ": " + ec.message() + " (expected a folder of demonstrations)";
    return std::nullopt;
  }
  if (files.empty()) {
    *error = dir + ": no expert_*.csv trajectories (expected the module's expert demonstrations)";
    return std::nullopt;
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::optional<std::vector<CohortAttempt>> cohort_from_trajectories(
    const ScenarioModel& scenario, const std::vector<std::string>& trajectories,
    std::string* error, const std::function<void(const std::string&)>& progress) {
  std::vector<CohortAttempt> out;
  for (const std::string& path : trajectories) {
    if (progress) progress(path);
    auto device = open_input("replay:" + path, error, UdpDeviceOptions{}.disconnect_timeout_s,
                             scene_instrument_count(scenario.world));
    if (!device) return std::nullopt;
    World world(scenario.world);
    AttemptRun run = run_attempt(scenario, world, *device);
    if (run.bone_modelled && !run.bone_error.empty()) {
      *error = path + ": bone model: " + run.bone_error;
      return std::nullopt;
    }
    out.push_back({std::filesystem::path(path).filename().string(), std::move(run.metrics)});
  }
  return out;
}

std::string calibration_table(const Rubric& rubric, const Calibration& c) {
  std::string s;
  char line[256];
  std::snprintf(line, sizeof line, "%-32s %3s %11s %11s %11s %11s %11s\n", "metric", "n", "mean",
                "sd", "sd used", "min", "max");
  s += line;
  auto row = [&](const Benchmark& b, const char* mark) {
    std::snprintf(line, sizeof line, "%-32s %3zu %11.4g %11.4g %11.4g%s %11.4g %11.4g\n",
                  b.metric.c_str(), b.experts, b.mean, b.measured_sd, b.sd, mark, b.min, b.max);
    s += line;
  };
  for (const Benchmark& b : c.terms) row(b, b.floored ? "*" : " ");
  bool any_floor = false;
  for (const Benchmark& b : c.terms) any_floor = any_floor || b.floored;
  if (any_floor) s += "* the term's sd_floor: the experts differ less than that\n";
  if (c.task && c.task_min && rubric.task) {
    std::snprintf(line, sizeof line, "task: %s >= %.4g (the experts' mean %.4g, times the share)\n",
                  rubric.task->metric.c_str(), *c.task_min, c.task->mean);
    s += line;
  }
  std::snprintf(line, sizeof line, "pass score: %.4g (%zu experts)\n", c.pass_score, c.experts);
  s += line;
  return s;
}

}  // namespace acdr

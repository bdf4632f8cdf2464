// Expert benchmarks from a cohort: per metric the (trimmed) mean and sample SD of the experts,
// with the rubric term's floor where the experts hardly differ.
#include "assessment/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "assessment/scoring.hpp"

namespace acdr {
namespace {

std::optional<Benchmark> benchmark_of(const std::string& metric, double sd_floor,
                                      const std::vector<Metrics>& experts,
                                      const CalibrationMethod& method, std::string* error) {
  std::vector<double> values;
  values.reserve(experts.size());
  for (std::size_t i = 0; i < experts.size(); ++i) {
    const double* v = experts[i].find(metric);
    if (v == nullptr || !std::isfinite(*v)) {
      if (error) {
        *error = "expert " + std::to_string(i + 1) + " of " + std::to_string(experts.size()) +
                 (v == nullptr ? " has no value of '" : " has a non-finite value of '") + metric +
                 "' (expected every rubric metric in every expert attempt)";
      }
      return std::nullopt;
    }
    values.push_back(*v);
  }
  std::sort(values.begin(), values.end());
  Benchmark b;
  b.metric = metric;
  b.min = values.front();
  b.max = values.back();
  // Trim the same count from each end, never leaving fewer than two values.
  std::size_t cut = static_cast<std::size_t>(std::floor(method.trim_fraction * values.size()));
  while (cut > 0 && values.size() - 2 * cut < 2) --cut;
  const auto first = values.begin() + static_cast<std::ptrdiff_t>(cut);
  const auto last = values.end() - static_cast<std::ptrdiff_t>(cut);
  b.experts = static_cast<std::size_t>(last - first);
  double sum = 0.0;
  for (auto it = first; it != last; ++it) sum += *it;
  b.mean = sum / static_cast<double>(b.experts);
  double ss = 0.0;
  for (auto it = first; it != last; ++it) ss += (*it - b.mean) * (*it - b.mean);
  b.measured_sd = std::sqrt(ss / static_cast<double>(b.experts - 1));
  b.floored = b.measured_sd < sd_floor;
  b.sd = b.floored ? sd_floor : b.measured_sd;
  return b;
}

}  // namespace

std::optional<Calibration> calibrate(const Rubric& rubric, const std::vector<Metrics>& experts,
                                     const CalibrationMethod& method, std::string* error) {
  if (experts.size() < 2) {
    if (error) {
      *error = "a cohort of " + std::to_string(experts.size()) +
               " expert attempt(s) (expected at least 2 for a mean and an SD)";
    }
    return std::nullopt;
  }
  if (!(method.trim_fraction >= 0.0 && method.trim_fraction < 0.5)) {
    if (error) *error = "trim fraction " + std::to_string(method.trim_fraction) + " (expected 0 to below 0.5)";
    return std::nullopt;
  }
  Calibration c;
  c.experts = experts.size();
  for (const RubricTerm& term : rubric.terms) {
    auto b = benchmark_of(term.metric, term.sd_floor, experts, method, error);
    if (!b) return std::nullopt;
    // A zero SD cannot score anything: without a floor the experts must differ.
    if (!(b->sd > 0.0)) {
      if (error) {
        *error = "every expert has " + term.metric + " = " + std::to_string(b->mean) +
                 " and the term has no sd_floor (expected a spread, or an sd_floor in the term)";
      }
      return std::nullopt;
    }
    c.terms.push_back(*b);
  }
  if (rubric.task) {
    auto b = benchmark_of(rubric.task->metric, 0.0, experts, method, error);
    if (!b) return std::nullopt;
    c.task = *b;
    c.task_min = method.task_share * b->mean;
  }
  c.pass_score = std::clamp(50.0 - 10.0 * method.pass_sds, 0.0, 100.0);
  return c;
}

Rubric apply_calibration(const Rubric& rubric, const Calibration& calibration) {
  Rubric r = rubric;
  for (std::size_t i = 0; i < r.terms.size() && i < calibration.terms.size(); ++i) {
    r.terms[i].expert_mean = calibration.terms[i].mean;
    r.terms[i].expert_sd = calibration.terms[i].sd;
  }
  if (r.task && calibration.task_min) r.task->min = *calibration.task_min;
  r.pass_score = calibration.pass_score;
  return r;
}

std::optional<std::vector<LeaveOneOut>> leave_one_out(const Rubric& rubric,
                                                      const std::vector<Metrics>& experts,
                                                      const CalibrationMethod& method,
                                                      std::string* error) {
  std::vector<LeaveOneOut> out;
  for (std::size_t i = 0; i < experts.size(); ++i) {
    std::vector<Metrics> others;
    for (std::size_t j = 0; j < experts.size(); ++j) {
      if (j != i) others.push_back(experts[j]);
    }
    auto c = calibrate(rubric, others, method, error);
    if (!c) return std::nullopt;
    out.push_back({i, score_attempt(experts[i], apply_calibration(rubric, *c))});
  }
  return out;
}

}  // namespace acdr

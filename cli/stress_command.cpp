// The body of `acdr stress`: run the built-in sweep and print the figures.
#include "cli/stress_command.hpp"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "stress/stress_case.hpp"

namespace acdr {

int run_stress(const StressOptions& options, std::ostream& out, std::ostream& err) {
  std::vector<StressResult> results;
  for (const auto& spec : builtin_stress_cases(options.fast)) {
    results.push_back(run_stress_case(spec));
    if (!options.json) {
      const StressResult& r = results.back();
      if (results.size() == 1) {
        char head[256];
        std::snprintf(head, sizeof head, "%-30s %-6s %4s %9s %11s %11s %6s %8s %8s %6s %8s\n",
                      "case", "passed", "nan", "v_max m/s", "KE_hold J", "dE_hold J", "tunnel",
                      "F_dev N", "limit N", "steps", "ms/step");
        out << head;
      }
      char line[512];
      std::snprintf(line, sizeof line,
                    "%-30s %-6s %4s %9.3f %11.3e %11.3e %6d %8.3f %8.3f %6d %8.2f",
                    r.name.c_str(), r.passed ? "yes" : "NO", r.nan ? "YES" : "no",
                    r.max_particle_speed_m_s, r.hold_kinetic_late_J, r.hold_energy_trend_J,
                    r.tunnelled, r.peak_device_force_N, r.device_limit_N, r.steps,
                    r.ms_per_step);
      out << line;
      if (r.nan && !r.nan_stage.empty()) out << "  (numerical: " << r.nan_stage << ")";
      if (r.into_instrument > 0) out << "  (" << r.into_instrument << " overlapped the instrument)";
      out << '\n';
      out.flush();
    }
  }
  bool passed = !results.empty();
  for (const auto& r : results) passed = passed && r.passed;
  if (options.json) {
    nlohmann::json doc;
    doc["cases"] = nlohmann::json::array();
    for (const auto& r : results) {
      doc["cases"].push_back({{"name", r.name},
                              {"passed", r.passed},
                              {"nan", r.nan},
                              {"nan_stage", r.nan_stage},
                              {"max_particle_speed_m_s", r.max_particle_speed_m_s},
                              {"hold_kinetic_energy_start_J", r.hold_energy_start_J},
                              {"hold_kinetic_energy_end_J", r.hold_energy_end_J},
                              {"hold_energy_change_J", r.hold_energy_change_J},
                              {"hold_kinetic_early_J", r.hold_kinetic_early_J},
                              {"hold_kinetic_late_J", r.hold_kinetic_late_J},
                              {"hold_energy_trend_J", r.hold_energy_trend_J},
                              {"hold_energy_jitter_J", r.hold_energy_jitter_J},
                              {"energy_grew", r.energy_grew},
                              {"tunnelled_particles", r.tunnelled},
                              {"instrument_overlaps", r.into_instrument},
                              {"peak_device_force_N", r.peak_device_force_N},
                              {"device_limit_N", r.device_limit_N},
                              {"rejected_device_samples", r.rejected_samples},
                              {"particles", r.particles},
                              {"steps", r.steps},
                              {"ms_per_step", r.ms_per_step}});
    }
    doc["passed"] = passed;
    out << doc.dump(2) << '\n';
  } else {
    std::size_t failed = 0;
    for (const auto& r : results) failed += r.passed ? 0 : 1;
    out << (passed ? "all " + std::to_string(results.size()) + " stress cases passed"
                   : std::to_string(failed) + " of " + std::to_string(results.size()) +
                         " stress cases FAILED")
        << '\n';
  }
  (void)err;
  return passed ? 0 : 1;
}

}  // namespace acdr

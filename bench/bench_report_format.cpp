// Table, CSV and JSON of a benchmark report.
#include "bench/bench_report_format.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace acdr {
namespace {

std::string num(double v, int precision = 3) {
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

nlohmann::json point_json(const WorkPoint& p) {
  nlohmann::json settings = {{"dt_s", p.dt_s}, {"spacing_m", p.spacing_m}};
  if (p.solver == "acdr") {
    settings["tolerance"] = p.tolerance;
  } else {
    settings["position_iterations"] = p.iterations;
    settings["link_stiffness"] = p.link_stiffness;
  }
  return {{"scene", p.scene},
          {"solver", p.solver},
          {"settings", settings},
          {"label", p.settings},
          {"particles", p.particles},
          {"links", p.links},
          {"wall_s_per_sim_s", p.wall_s_per_sim_s},
          {"cpu_s_per_sim_s", p.cpu_s_per_sim_s},
          {"timing_runs", p.timing_runs},
          {"slowest_wall_s_per_sim_s", p.slowest_wall_s_per_sim_s},
          {"mean_step_ms", p.mean_step_ms},
          {"p99_step_ms", p.p99_step_ms},
          {"cpu_us_per_particle_step", p.cpu_us_per_particle_step},
          {"force_rms_error", p.force_rms_error},
          {"force_peak_error", p.force_peak_error},
          {"removed_error", p.removed_error},
          {"mean_iterations", p.mean_iterations},
          {"mean_active", p.mean_active},
          {"default", p.is_default},
          {"reference", p.is_reference},
          {"failed", p.failed}};
}

}  // namespace

void write_bench_table(const BenchReport& r, std::ostream& out) {
  out << "Work-precision (errors against each scene's reference run; windows:";
  for (const auto& [scene, w] : r.windows)
    out << " " << scene << " " << num(w.start_s) << " s + " << num(w.duration_s) << " s after "
        << num(w.lead_s) << " s of lead";
  out << ")\n";
  out << std::left << std::setw(11) << "scene" << std::setw(8) << "solver" << std::setw(44)
      << "settings" << std::right << std::setw(8) << "N" << std::setw(9) << "links"
      << std::setw(11) << "wall s/s" << std::setw(10) << "cpu s/s" << std::setw(9) << "mean ms"
      << std::setw(9) << "p99 ms" << std::setw(11) << "us/part-st" << std::setw(11) << "F rms"
      << std::setw(11) << "F peak" << std::setw(10) << "removed" << std::setw(8) << "iters"
      << "\n";
  for (const WorkPoint& p : r.points) {
    out << std::left << std::setw(11) << p.scene << std::setw(8) << p.solver << std::setw(44)
        << p.settings << std::right << std::setw(8) << p.particles << std::setw(9) << p.links
        << std::setw(11) << num(p.wall_s_per_sim_s) << std::setw(10) << num(p.cpu_s_per_sim_s)
        << std::setw(9) << num(p.mean_step_ms) << std::setw(9) << num(p.p99_step_ms)
        << std::setw(11) << num(p.cpu_us_per_particle_step) << std::setw(11)
        << num(p.force_rms_error) << std::setw(11) << num(p.force_peak_error) << std::setw(10)
        << num(p.removed_error) << std::setw(8) << num(p.mean_iterations)
        << (p.failed ? "  FAILED" : "") << "\n";
  }
  out << "\nScaling (" << r.scaling_scene
      << ", every particle awake, blade in the material; CPU time per step";
  if (!r.scaling.empty() && r.scaling.front().timing_runs > 1)
    out << ", fastest of " << r.scaling.front().timing_runs << " runs";
  out << ")\n";
  out << std::right << std::setw(8) << "h mm" << std::setw(9) << "N" << std::setw(12)
      << "wall ms" << std::setw(11) << "cpu ms" << std::setw(9) << "p99 ms" << std::setw(8)
      << "iters" << std::setw(13) << "us/part-st" << std::setw(16) << "us/iter/part" << "\n";
  for (const ScalingPoint& p : r.scaling)
    out << std::setw(8) << num(p.spacing_m * 1e3) << std::setw(9) << p.particles
        << std::setw(12) << num(p.wall_ms_per_step) << std::setw(11) << num(p.cpu_ms_per_step)
        << std::setw(9) << num(p.p99_step_ms) << std::setw(8) << num(p.mean_iterations)
        << std::setw(13) << num(p.cpu_us_per_particle_step) << std::setw(16)
        << num(p.cpu_us_per_iteration_per_particle) << "\n";
  out << "fit: cost ~ N^" << num(r.scaling_fit.exponent) << " (r2 " << num(r.scaling_fit.r2)
      << "); per PCG iteration ~ N^" << num(r.per_iteration_fit.exponent) << "\n";
  out << "\nSkips (" << r.skips_scene << "; on = the default; error of on against off)\n";
  out << std::left << std::setw(18) << "skip" << std::right << std::setw(12) << "on cpu s/s"
      << std::setw(13) << "off cpu s/s" << std::setw(8) << "gain" << std::setw(11) << "F rms"
      << std::setw(10) << "removed" << "\n";
  for (const SkipResult& s : r.skips) {
    out << std::left << std::setw(18) << s.name << std::right;
    if (!s.measured) {
      out << "  not measured\n";
      continue;
    }
    const bool wall = s.name == "headless";
    out << std::setw(12) << num(wall ? s.on_wall_s_per_sim_s : s.on_cpu_s_per_sim_s)
        << std::setw(13) << num(wall ? s.off_wall_s_per_sim_s : s.off_cpu_s_per_sim_s)
        << std::setw(8) << num(s.gain) << std::setw(11) << num(s.force_rms_error)
        << std::setw(10) << num(s.removed_error) << (wall ? "  (wall time)" : "") << "\n";
  }
  if (!r.bone.empty()) {
    out << "\nBone (each load sample of the window solved as an attempt's worker solves it; per "
           "vertebra solve = one load update; fastest of the timing runs)\n";
    out << std::left << std::setw(7) << "scene" << std::right << std::setw(8) << "size mm"
        << std::setw(9) << "dofs" << std::setw(11) << "L nnz" << std::setw(9) << "samples"
        << std::setw(8) << "solves" << std::setw(8) << "loads" << std::setw(12) << "cpu ms med"
        << std::setw(10) << "cpu p95" << std::setw(10) << "cpu max" << std::setw(13)
        << "wall ms med" << std::setw(10) << "wall p95" << "\n";
    for (const BoneSolveFigures& b : r.bone) {
      out << std::left << std::setw(7) << b.scene << std::right;
      if (!b.measured) {
        out << "  not measured: " << b.note << "\n";
        continue;
      }
      out << std::setw(8) << num(b.element_size_m * 1e3) << std::setw(9)
          << std::max(b.free_dofs[0], b.free_dofs[1]) << std::setw(11)
          << num(double(std::max(b.factor_nonzeros[0], b.factor_nonzeros[1])), 3) << std::setw(9)
          << b.samples << std::setw(8) << b.solves << std::setw(8) << num(b.mean_loads_per_solve)
          << std::setw(12) << num(b.solve_cpu.median_ms) << std::setw(10)
          << num(b.solve_cpu.p95_ms) << std::setw(10) << num(b.solve_cpu.max_ms) << std::setw(13)
          << num(b.solve_wall.median_ms) << std::setw(10) << num(b.solve_wall.p95_ms) << "\n";
    }
  }
  out << "\nmachine: " << r.machine << "\nbenchmark wall time: " << num(r.wall_s, 4) << " s\n";
}

void write_bench_csv(const BenchReport& r, std::ostream& f) {
  f << "kind,scene,solver,settings,particles,links,wall_s_per_sim_s,cpu_s_per_sim_s,"
       "force_rms_error,force_peak_error,removed_error,mean_iterations,default,reference,"
       "spacing_m,cpu_ms_per_step,wall_ms_per_step,gain,p99_step_ms,cpu_us_per_particle_step\n";
  for (const WorkPoint& p : r.points)
    f << "point," << p.scene << "," << p.solver << ",\"" << p.settings << "\"," << p.particles
      << "," << p.links << "," << p.wall_s_per_sim_s << "," << p.cpu_s_per_sim_s << ","
      << p.force_rms_error << "," << p.force_peak_error << "," << p.removed_error << ","
      << p.mean_iterations << "," << p.is_default << "," << p.is_reference << "," << p.spacing_m
      << ",," << p.mean_step_ms << ",," << p.p99_step_ms << "," << p.cpu_us_per_particle_step
      << "\n";
  for (const ScalingPoint& p : r.scaling)
    f << "scaling," << r.scaling_scene << ",acdr,\"all awake\"," << p.particles << ",,,,,,,"
      << p.mean_iterations << ",,," << p.spacing_m << "," << p.cpu_ms_per_step << ","
      << p.wall_ms_per_step << ",," << p.p99_step_ms << "," << p.cpu_us_per_particle_step
      << "\n";
  for (const BoneSolveFigures& b : r.bone) {
    if (!b.measured) continue;
    f << "bone," << b.scene << ",acdr,\"vertebra solve, " << b.solves << " solves\",,,,,,,,,,,"
      << b.element_size_m << "," << b.solve_cpu.median_ms << "," << b.solve_wall.median_ms
      << ",,,\n";
  }
  for (const SkipResult& s : r.skips) {
    if (!s.measured) continue;
    f << "skip," << r.skips_scene << ",acdr,\"" << s.name << " on\",,," << s.on_wall_s_per_sim_s
      << "," << s.on_cpu_s_per_sim_s << "," << s.force_rms_error << ",," << s.removed_error
      << ",,,,,,," << s.gain << ",,\n";
    f << "skip," << r.skips_scene << ",acdr,\"" << s.name << " off\",,," << s.off_wall_s_per_sim_s
      << "," << s.off_cpu_s_per_sim_s << ",0,,0,,,,,,,,,\n";
  }
}

nlohmann::json bench_report_json(const BenchReport& r) {
  nlohmann::json doc;
  doc["points"] = nlohmann::json::array();
  for (const WorkPoint& p : r.points) doc["points"].push_back(point_json(p));
  nlohmann::json scaling;
  scaling["scene"] = r.scaling_scene;
  scaling["condition"] = "every particle awake, blade in the material";
  scaling["points"] = nlohmann::json::array();
  for (const ScalingPoint& p : r.scaling)
    scaling["points"].push_back({{"spacing_m", p.spacing_m},
                                 {"particles", p.particles},
                                 {"wall_ms_per_step", p.wall_ms_per_step},
                                 {"cpu_ms_per_step", p.cpu_ms_per_step},
                                 {"mean_iterations", p.mean_iterations},
                                 {"p99_step_ms", p.p99_step_ms},
                                 {"cpu_us_per_particle_step", p.cpu_us_per_particle_step},
                                 {"cpu_us_per_iteration_per_particle",
                                  p.cpu_us_per_iteration_per_particle},
                                 {"timing_runs", p.timing_runs}});
  scaling["exponent"] = r.scaling_fit.exponent;
  scaling["r2"] = r.scaling_fit.r2;
  scaling["per_iteration_exponent"] = r.per_iteration_fit.exponent;
  doc["scaling"] = scaling;
  doc["skips"] = nlohmann::json::array();
  for (const SkipResult& s : r.skips) {
    nlohmann::json j = {{"name", s.name}, {"description", s.description}, {"measured", s.measured}};
    if (s.measured) {
      j["on_wall_s_per_sim_s"] = s.on_wall_s_per_sim_s;
      j["off_wall_s_per_sim_s"] = s.off_wall_s_per_sim_s;
      j["on_cpu_s_per_sim_s"] = s.on_cpu_s_per_sim_s;
      j["off_cpu_s_per_sim_s"] = s.off_cpu_s_per_sim_s;
      j["gain"] = s.gain;
      j["force_rms_error"] = s.force_rms_error;
      j["removed_error"] = s.removed_error;
    }
    doc["skips"].push_back(j);
  }
  doc["bone"] = nlohmann::json::array();
  auto timing = [](const TimingSummary& t) {
    return nlohmann::json{{"median_ms", t.median_ms}, {"mean_ms", t.mean_ms},
                          {"p95_ms", t.p95_ms}, {"max_ms", t.max_ms}};
  };
  for (const BoneSolveFigures& b : r.bone) {
    nlohmann::json j = {{"scene", b.scene}, {"measured", b.measured}};
    if (!b.measured) {
      j["note"] = b.note;
    } else {
      j["element_size_m"] = b.element_size_m;
      j["free_dofs"] = b.free_dofs;
      j["factor_nonzeros"] = b.factor_nonzeros;
      j["back_substitution_share"] = b.back_substitution_share;
      j["build_s"] = b.build_s;
      j["samples"] = b.samples;
      j["solves"] = b.solves;
      j["mean_loads_per_solve"] = b.mean_loads_per_solve;
      j["solve_cpu"] = timing(b.solve_cpu);
      j["solve_wall"] = timing(b.solve_wall);
      j["sample_cpu"] = timing(b.sample_cpu);
      j["sample_wall"] = timing(b.sample_wall);
    }
    doc["bone"].push_back(j);
  }
  doc["windows"] = nlohmann::json::object();
  for (const auto& [scene, w] : r.windows)
    doc["windows"][scene] = {
        {"start_s", w.start_s}, {"duration_s", w.duration_s}, {"lead_s", w.lead_s}};
  doc["quick"] = r.quick;
  doc["machine"] = r.machine;
  doc["wall_s"] = r.wall_s;
  return doc;
}


}  // namespace acdr

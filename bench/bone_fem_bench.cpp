// Bone finite-element benchmark: for each element size, mesh both vertebrae of the default
// C4-C5 segment (no cache, so the meshing is timed), build the elastic model (regions,
// assembly, factorisation) and solve a curette-like contact on the near endplate many times,
// each at a slightly different place (a new load). Prints a table and, with --csv, CSV rows:
// CPU (this thread) and wall times per stage, and the mesh and factor sizes.
//
//   acdr_bone_fem_bench [--sizes 2.0,1.5,1.0] [--order linear|quadratic]
//                       [--solver cholmod|eigen-llt] [--repeats 50] [--csv FILE]
//   acdr_bone_fem_bench --scene SCENARIO.json:TRAJECTORY.csv[@START_S[+DURATION_S]]
//                       [--repeats 3]
// solve = contact forces and substitution; update = solve plus the stress recovery (element
// and nodal stresses), i.e. one load update; CPU times are this thread's.
// --scene runs the scenario along the trajectory window (default: all of it), keeps the bone
// load samples the world takes and solves them as an attempt's worker does (the scenario's
// bone model, meshes from the cache): per vertebra solve and per sample, CPU and wall.
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bone_solve_bench.hpp"
#include "bench/scene_run.hpp"
#include "engine/anatomy/anatomy.hpp"
#include "engine/anatomy/vertebra_generator.hpp"
#include "engine/bone/bone_fem.hpp"
#include "scenarios/scenario_loader.hpp"

namespace {

using namespace acdr;

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Row {
  std::string vertebra;
  double size_mm = 0;
  std::size_t nodes = 0, tets = 0, dofs = 0, factor_nnz = 0;
  double mesh_s = 0, classify_s = 0, assemble_s = 0, factor_s = 0;  // wall
  double build_cpu_s = 0;
  double cached_s = 0;  // loading the same mesh from the disk cache (a second start)
  double solve_wall_ms = 0, update_wall_ms = 0, update_cpu_ms = 0;
  double min_dihedral = 0, max_aspect = 0;
};

void print_timing(const char* what, const TimingSummary& t) {
  std::printf("  %-28s median %7.3f  mean %7.3f  p95 %7.3f  max %7.3f ms\n", what, t.median_ms,
              t.mean_ms, t.p95_ms, t.max_ms);
}

// --scene: the scenario's bone model on the loads of a run along the trajectory.
int scene_bench(const std::string& spec, int repeats) {
  const auto colon = spec.rfind(':');
  if (colon == std::string::npos) {
    std::fprintf(stderr, "--scene '%s': expected SCENARIO.json:TRAJECTORY.csv[@START[+DUR]]\n",
                 spec.c_str());
    return 2;
  }
  std::string trajectory_path = spec.substr(colon + 1);
  RunWindow window;
  if (const auto at = trajectory_path.find('@'); at != std::string::npos) {
    const std::string times = trajectory_path.substr(at + 1);
    trajectory_path.resize(at);
    window.start_s = std::atof(times.c_str());
    if (const auto plus = times.find('+'); plus != std::string::npos)
      window.duration_s = std::atof(times.c_str() + plus + 1);
  }
  const LoadResult loaded = load_scenario_file(spec.substr(0, colon));
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", loaded.errors.empty() ? "cannot load the scenario"
                                                       : loaded.errors.front().to_string().c_str());
    return 2;
  }
  const ScenarioModel& scenario = *loaded.model;
  if (!scenario.bone.enabled) {
    std::fprintf(stderr, "%s: the scenario does not model the bone\n", scenario.path.c_str());
    return 2;
  }
  std::string error;
  auto trajectory = Trajectory::load_csv(trajectory_path, &error);
  if (!trajectory) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }
  const double w0 = wall_seconds();
  const std::vector<BoneLoadRecord> samples =
      sample_bone_loads(scenario.world, *trajectory, window);
  const double run_s = wall_seconds() - w0;
  const Anatomy anatomy(scenario.world.anatomy);
  auto bone = BoneSegment::build(anatomy, scenario.bone,
                                 anatomy_cache_dir(scenario.world.anatomy, "bone"), &error);
  if (!bone) {
    std::fprintf(stderr, "bone model: %s\n", error.c_str());
    return 1;
  }
  const BoneSolveFigures f = time_bone_solves(*bone, samples, repeats);
  std::printf("%s along %s (%zu samples taken in %.1f s of run)\n", scenario.path.c_str(),
              trajectory_path.c_str(), f.samples, run_s);
  std::printf("  element size %.2f mm; free dofs C4 %zu C5 %zu; factor nnz C4 %zu C5 %zu; build "
              "%.2f s\n",
              f.element_size_m * 1e3, f.free_dofs[0], f.free_dofs[1], f.factor_nonzeros[0],
              f.factor_nonzeros[1], f.build_s);
  std::printf("  back substitution of the measured elements: %.0f %% (C4), %.0f %% (C5) of the factor\n",
              100.0 * f.back_substitution_share[0], 100.0 * f.back_substitution_share[1]);
  std::printf("  %zu vertebra solves, %.1f patch loads each on average (fastest of %d)\n",
              f.solves, f.mean_loads_per_solve, repeats);
  print_timing("per vertebra solve, CPU", f.solve_cpu);
  print_timing("per vertebra solve, wall", f.solve_wall);
  print_timing("per loaded sample, CPU", f.sample_cpu);
  print_timing("per loaded sample, wall", f.sample_wall);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> sizes_mm = {2.0, 1.5, 1.0};
  TetOrder order = TetOrder::kLinear;
  SparseSolverKind solver = SparseSolverKind::kCholmod;
  int repeats = 50;
  std::string csv, scene;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--sizes") {
      sizes_mm.clear();
      std::stringstream list(next());
      for (std::string s; std::getline(list, s, ',');) sizes_mm.push_back(std::atof(s.c_str()));
    } else if (a == "--order") {
      order = next() == "quadratic" ? TetOrder::kQuadratic : TetOrder::kLinear;
    } else if (a == "--solver") {
      solver = next() == "eigen-llt" ? SparseSolverKind::kEigenLLT : SparseSolverKind::kCholmod;
    } else if (a == "--repeats") {
      repeats = std::max(1, std::atoi(next().c_str()));
    } else if (a == "--csv") {
      csv = next();
    } else if (a == "--scene") {
      scene = next();
    } else {
      std::fprintf(stderr, "unknown argument %s\n", a.c_str());
      return 2;
    }
  }

  if (!scene.empty()) return scene_bench(scene, repeats == 50 ? 3 : repeats);

  const SegmentParams segment;
  const SegmentLandmarks marks = segment_landmarks(segment);
  std::vector<Row> rows;
  std::printf("%-4s %6s %7s %8s %8s %10s %8s %8s %8s %8s %8s %9s %9s %9s %7s %6s\n", "", "size",
              "nodes", "tets", "dofs", "L_nnz", "mesh_s", "cache_s", "class_s", "asm_s", "fact_s",
              "solve_ms", "update_ms", "updCPU_ms", "min_dih", "maxAR");
  for (double size_mm : sizes_mm) {
    for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
      const TriangleMesh surface = generate_vertebra(segment, level);
      BoneFemConfig config;
      config.meshing.size_m = size_mm * 1e-3;
      config.order = order;
      config.solver = solver;
      BoneFemReport report;
      std::string error;
      const double cpu0 = thread_cpu_seconds();
      auto bone = BoneFem::build(surface, segment, level, config, "", &report, &error);
      const double build_cpu = thread_cpu_seconds() - cpu0;
      if (!bone) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
      }
      // The contact: a 20 N push into the near endplate, moving over a 4 mm square.
      const bool c4 = level == VertebraLevel::kC4;
      const double y = c4 ? marks.c4_lower_endplate_y_m : marks.c5_upper_endplate_y_m;
      const Vec3 inward(0.0, c4 ? 1.0 : -1.0, 0.0);
      BoneSolution solution;
      std::vector<double> solve, wall, cpu;
      for (int r = -3; r < repeats; ++r) {  // three warm-up solves
        ContactLoad contact;
        contact.point_m = Vec3(1e-3 * ((r % 5) - 2) * 0.8, y, 1e-3 * ((r % 7) - 3) * 0.6);
        contact.force_N = 20.0 * inward;
        const double w0 = wall_seconds(), c0 = thread_cpu_seconds();
        bone->solve({&contact, 1}, solution);
        if (r < 0) continue;
        wall.push_back(1e3 * (wall_seconds() - w0));
        cpu.push_back(1e3 * (thread_cpu_seconds() - c0));
        solve.push_back(1e3 * solution.solve_seconds);
      }
      Row row;
      row.vertebra = vertebra_level_name(level);
      row.size_mm = size_mm;
      row.nodes = report.elastic.nodes;
      row.tets = report.elastic.elements;
      row.dofs = report.elastic.free_dofs;
      row.factor_nnz = report.elastic.factor_nonzeros;
      row.mesh_s = report.mesh.seconds;
      row.classify_s = report.classify_seconds;
      row.assemble_s = report.elastic.assemble_seconds;
      row.factor_s = report.elastic.factor_seconds;
      row.build_cpu_s = build_cpu;
      row.solve_wall_ms = median(solve);
      row.update_wall_ms = median(wall);
      row.update_cpu_ms = median(cpu);
      row.min_dihedral = report.mesh.quality.min_dihedral_deg;
      row.max_aspect = report.mesh.quality.max_aspect_ratio;
      // A second start: the mesh stored once, then loaded.
      {
        const std::string dir = (std::filesystem::temp_directory_path() /
                                 ("acdr_bone_bench_" + std::to_string(::getpid())))
                                    .string();
        TetMeshLoadInfo info;
        load_or_mesh_surface(surface, config.meshing, dir, &info, &error);
        load_or_mesh_surface(surface, config.meshing, dir, &info, &error);
        row.cached_s = info.from_cache ? info.seconds : -1.0;
        std::filesystem::remove_all(dir);
      }
      rows.push_back(row);
      std::printf(
          "%-4s %6.2f %7zu %8zu %8zu %10zu %8.2f %8.3f %8.3f %8.3f %8.3f %9.3f %9.3f %9.3f %7.2f "
          "%6.1f\n",
          row.vertebra.c_str(), row.size_mm, row.nodes, row.tets, row.dofs, row.factor_nnz,
          row.mesh_s, row.cached_s, row.classify_s, row.assemble_s, row.factor_s, row.solve_wall_ms,
          row.update_wall_ms, row.update_cpu_ms, row.min_dihedral, row.max_aspect);
      std::fflush(stdout);
    }
  }
  std::printf(
      "%s tetrahedra, %s; wall times except updCPU; solve: contact forces and "
      "substitution; update: solve and stresses (medians of %d)\n",
      tet_order_name(order), sparse_solver_name(solver), repeats);
  if (!csv.empty()) {
    std::ofstream out(csv);
    out << "vertebra,size_mm,order,solver,nodes,tets,free_dofs,factor_nnz,mesh_s,cached_s,classify_"
           "s,"
           "assemble_s,"
           "factor_s,build_cpu_s,solve_wall_ms,update_wall_ms,update_cpu_ms,min_dihedral_deg,"
           "max_aspect_ratio\n";
    for (const Row& r : rows)
      out << r.vertebra << ',' << r.size_mm << ',' << tet_order_name(order) << ','
          << sparse_solver_name(solver) << ',' << r.nodes << ',' << r.tets << ',' << r.dofs << ','
          << r.factor_nnz << ',' << r.mesh_s << ',' << r.cached_s << ',' << r.classify_s << ','
          << r.assemble_s << ',' << r.factor_s << ',' << r.build_cpu_s << ',' << r.solve_wall_ms
          << ',' << r.update_wall_ms << ',' << r.update_cpu_ms << ',' << r.min_dihedral << ','
          << r.max_aspect << '\n';
    if (!out) {
      std::fprintf(stderr, "could not write %s\n", csv.c_str());
      return 1;
    }
  }
  return 0;
}

// Timing the bone's solves on the load samples of a scene run: see bone_solve_bench.hpp.
#include "bench/bone_solve_bench.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bench/scene_run.hpp"

namespace acdr {

TimingSummary summarize_ms(std::vector<double> ms) {
  TimingSummary s;
  if (ms.empty()) return s;
  std::sort(ms.begin(), ms.end());
  double sum = 0.0;
  for (double v : ms) sum += v;
  s.mean_ms = sum / static_cast<double>(ms.size());
  s.median_ms = ms[ms.size() / 2];
  s.p95_ms = ms[std::min(ms.size() - 1, static_cast<std::size_t>(std::ceil(0.95 * ms.size())) - 1)];
  s.max_ms = ms.back();
  return s;
}

std::vector<BoneLoadRecord> sample_bone_loads(const WorldConfig& world, const Trajectory& trajectory,
                                              const RunWindow& window) {
  std::vector<BoneLoadRecord> out;
  run_scene(world, trajectory, window, {}, [&](const World& w, const Frame&) {
    const BoneLoadSample* s = w.bone_loads();
    if (!s) return;
    BoneLoadRecord r;
    r.t_s = s->t_s;
    r.points.assign(s->points.begin(), s->points.begin() + s->count);
    out.push_back(std::move(r));
  });
  return out;
}

BoneSolveFigures time_bone_solves(const BoneSegment& bone,
                                  const std::vector<BoneLoadRecord>& samples, int repeats) {
  BoneSolveFigures f;
  f.measured = true;
  f.element_size_m = bone.config().fem.meshing.size_m;
  f.build_s = bone.build_seconds();
  for (int v = 0; v < 2; ++v) {
    f.free_dofs[v] = bone.vertebra(v).model().report().free_dofs;
    f.factor_nonzeros[v] = bone.vertebra(v).model().report().factor_nonzeros;
    if (f.factor_nonzeros[v] > 0)
      f.back_substitution_share[v] =
          static_cast<double>(bone.measured_solve(v).needed_factor_nonzeros) /
          static_cast<double>(f.factor_nonzeros[v]);
  }
  f.samples = samples.size();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Per (sample, vertebra): the fastest of the repeats; -1 where not solved.
  std::vector<std::array<double, 2>> cpu(samples.size(), {kInf, kInf}),
      wall(samples.size(), {kInf, kInf});
  std::vector<double> sample_cpu(samples.size(), kInf), sample_wall(samples.size(), kInf);
  std::vector<std::array<bool, 2>> solved(samples.size(), {false, false});
  BoneSegmentScratch scratch;
  std::size_t loads_on_solved = 0;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const BoneSampleResult res = bone.solve(samples[i].t_s, samples[i].points, scratch);
      solved[i] = res.solved;
      double c = 0.0, w = 0.0;
      for (int v = 0; v < 2; ++v) {
        if (!res.solved[v]) continue;
        cpu[i][v] = std::min(cpu[i][v], 1e3 * res.cpu_s[v]);
        wall[i][v] = std::min(wall[i][v], 1e3 * res.wall_s[v]);
        c += res.cpu_s[v];
        w += res.wall_s[v];
        if (r == 0)
          for (const BoneLoadPoint& p : samples[i].points) loads_on_solved += p.vertebra == v;
      }
      if (res.solved[0] || res.solved[1]) {
        sample_cpu[i] = std::min(sample_cpu[i], 1e3 * c);
        sample_wall[i] = std::min(sample_wall[i], 1e3 * w);
      }
    }
  }
  std::vector<double> sc, sw, pc, pw;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    for (int v = 0; v < 2; ++v) {
      if (!solved[i][v]) continue;
      sc.push_back(cpu[i][v]);
      sw.push_back(wall[i][v]);
    }
    if (solved[i][0] || solved[i][1]) {
      pc.push_back(sample_cpu[i]);
      pw.push_back(sample_wall[i]);
    }
  }
  f.solves = sc.size();
  f.mean_loads_per_solve =
      f.solves > 0 ? static_cast<double>(loads_on_solved) / static_cast<double>(f.solves) : 0.0;
  f.solve_cpu = summarize_ms(sc);
  f.solve_wall = summarize_ms(sw);
  f.sample_cpu = summarize_ms(pc);
  f.sample_wall = summarize_ms(pw);
  return f;
}

}  // namespace acdr

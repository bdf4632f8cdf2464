// The segment's two vertebrae under an attempt's sampled loads.
#include "engine/bone/bone_segment.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

namespace acdr {
namespace {

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

const char* bone_measure_name(BoneMeasure m) {
  switch (m) {
    case BoneMeasure::kC4InferiorEndplate: return "C4 inferior endplate";
    case BoneMeasure::kC5SuperiorEndplate: return "C5 superior endplate";
    case BoneMeasure::kC4Posterior: return "C4 pedicles and foramina";
    case BoneMeasure::kC5Posterior: return "C5 pedicles and foramina";
  }
  return "?";
}


std::vector<std::uint32_t> bone_measure_elements(const BoneFem& fem, BoneMeasure measure,
                                                 double reach_m) {
  const TetMesh& mesh = fem.mesh();
  const VertebraBodyFrame& body = fem.body();
  // The disc side: down from C4's centre, up from C5's.
  const double near = fem.level() == VertebraLevel::kC4 ? -1.0 : 1.0;
  const bool endplate = bone_measure_is_endplate(measure);
  std::vector<std::uint32_t> out;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto region = static_cast<BoneRegion>(fem.labels().region[t]);
    Vec3 c = Vec3::Zero();
    for (std::uint32_t n : mesh.tets[t]) c += mesh.nodes[n];
    c = c / 4.0 - body.center_m;
    if (endplate) {
      if (region == BoneRegion::kEndplate && near * c.y() > 0.0)
        out.push_back(static_cast<std::uint32_t>(t));
    } else if (region == BoneRegion::kPosterior && c.z() >= body.back_z_m - reach_m) {
      out.push_back(static_cast<std::uint32_t>(t));
    }
  }
  return out;
}

std::unique_ptr<BoneSegment> BoneSegment::build(const Anatomy& anatomy,
                                                const BoneModelConfig& config,
                                                const std::string& cache_dir, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  if (std::string bad = validate_bone_model_config(config); !bad.empty()) {
    bad.pop_back();
    if (error) *error = "bad bone model configuration: " + bad;
    return nullptr;
  }
  std::unique_ptr<BoneSegment> seg(new BoneSegment());
  seg->config_ = config;
  for (int v = 0; v < 2; ++v) {
    const VertebraLevel level = v == 0 ? VertebraLevel::kC4 : VertebraLevel::kC5;
    seg->fem_[v] = BoneFem::build(anatomy.vertebra(level), anatomy.config().segment, level,
                                  config.fem, cache_dir, nullptr, error);
    if (!seg->fem_[v]) return nullptr;
  }
  for (int m = 0; m < kBoneMeasureCount; ++m) {
    const auto measure = static_cast<BoneMeasure>(m);
    seg->elements_[m] = bone_measure_elements(*seg->fem_[bone_measure_vertebra(measure)], measure);
    if (seg->elements_[m].empty()) {
      if (error)
        *error = std::string(bone_measure_name(measure)) +
                 ": no elements there (is the mesh in the segment frame?)";
      return nullptr;
    }
  }
  for (int v = 0; v < 2; ++v) {
    std::vector<std::uint32_t> measured;
    for (int m = 0; m < kBoneMeasureCount; ++m)
      if (bone_measure_vertebra(static_cast<BoneMeasure>(m)) == v)
        measured.insert(measured.end(), seg->elements_[m].begin(), seg->elements_[m].end());
    std::sort(measured.begin(), measured.end());
    measured.erase(std::unique(measured.begin(), measured.end()), measured.end());
    seg->measured_[v] = seg->fem_[v]->model().partial_solve_for(measured);
  }
  seg->build_seconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return seg;
}

BoneSampleResult BoneSegment::solve(double t_s, std::span<const BoneLoadPoint> loads,
                                    BoneSegmentScratch& scratch) const {
  BoneSampleResult r;
  r.t_s = t_s;
  for (const BoneLoadPoint& p : loads) r.load_N += p.force_N.cast<double>().norm();
  for (int v = 0; v < 2; ++v) {
    scratch.contacts.clear();
    double sum = 0.0;
    for (const BoneLoadPoint& p : loads) {
      if (p.vertebra != v) continue;
      ContactLoad c;
      c.point_m = p.point_m.cast<double>();
      c.force_N = p.force_N.cast<double>();
      if (p.radius_m > 0.0f) c.radius_m = p.radius_m;
      scratch.contacts.push_back(c);
      sum += c.force_N.norm();
    }
    if (!(sum >= config_.min_load_N) || scratch.contacts.empty()) continue;
    BoneSolution& sol = scratch.solution[v];
    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = thread_cpu_seconds();
    fem_[v]->solve(scratch.contacts, sol, scratch.nodal_fields,
                   scratch.nodal_fields ? nullptr : &measured_[v]);
    r.solved[v] = true;
    for (int m = 0; m < kBoneMeasureCount; ++m) {
      const auto measure = static_cast<BoneMeasure>(m);
      if (bone_measure_vertebra(measure) != v) continue;
      double peak = 0.0;
      for (std::uint32_t t : elements_[m]) peak = std::max(peak, sol.element_von_mises_Pa[t]);
      r.peak_Pa[m] = peak;
    }
    r.cpu_s[v] = thread_cpu_seconds() - cpu0;
    r.wall_s[v] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  }
  return r;
}

}  // namespace acdr

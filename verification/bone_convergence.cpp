// bone_convergence: the mesh-convergence test of a vertebra, as the seed paper's authors ran
// one on their C4-C5 model. The default C5 is meshed at three or four element sizes (a ratio
// of sqrt 2 between them) and loaded by the same contact: a curette tip pressing 20 N into the
// middle of its upper endplate over a 1.5 mm patch (a point load would not do: the stress under
// a point is infinite and its computed peak grows as the mesh is refined). For each mesh: the
// peak von Mises stress of the elements within 3 mm of the contact (the bony endplate under
// the patch: the shell's own stress, bone_material.hpp), and the volume-mean von Mises stress
// of the cancellous elements within the same distance (the core under the contact; the mean
// leaves out shell elements, whose share of the volume shrinks as the mesh is refined).
//
// The observed order p and the extrapolated value follow Richardson extrapolation for unequal
// refinement ratios (Celik et al., J Fluids Eng 2008;130:078001), with the element size taken
// as the cube root of the mean element volume. Checks: the changes shrink as the mesh is
// refined (the ratio of the last change to the one before is below 1), and the finest mesh is
// within the tolerance of the extrapolated value (its discretisation error; 25 %: the core's
// mean converges slowly because the shell layer it excludes thins as the mesh is refined).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/anatomy/vertebra_generator.hpp"
#include "engine/bone/bone_fem.hpp"
#include "verification/bone_cases.hpp"
#include "verification/cases.hpp"

namespace acdr::verification {
namespace {

struct Sample {
  double target_m = 0.0;  // the mesher's size
  double size_m = 0.0;    // cube root of the mean element volume
  double peak_Pa = 0.0, mean_Pa = 0.0;
  std::size_t nodes = 0, tets = 0;
};

/// Order and extrapolated value from three solutions, coarse to fine (Celik et al. 2008).
void richardson(const Sample& coarse, const Sample& mid, const Sample& fine, double Sample::*f,
                double* order, double* extrapolated) {
  const double r21 = mid.size_m / fine.size_m, r32 = coarse.size_m / mid.size_m;
  const double e21 = mid.*f - fine.*f, e32 = coarse.*f - mid.*f;
  if (e21 == 0.0 || e32 == 0.0) {
    *order = std::nan("");
    *extrapolated = fine.*f;
    return;
  }
  const double s = e32 / e21 > 0.0 ? 1.0 : -1.0;
  double p = std::abs(std::log(std::abs(e32 / e21))) / std::log(r21);
  for (int it = 0; it < 50; ++it) {
    const double q = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
    p = std::abs(std::log(std::abs(e32 / e21)) + q) / std::log(r21);
  }
  *order = p;
  *extrapolated = (std::pow(r21, p) * fine.*f - mid.*f) / (std::pow(r21, p) - 1.0);
}

}  // namespace

VerificationCaseSpec bone_convergence_defaults(bool fast) {
  VerificationCaseSpec s;
  // The fast form leaves out the coarsest mesh, which is outside the asymptotic range.
  s.params.push_back({"size_1_m", fast ? 0.0 : 2.0e-3, "m", "coarsest element size (0: none)"});
  s.params.push_back({"size_2_m", 1.4142e-3, "m", "element size"});
  s.params.push_back({"size_3_m", 1.0e-3, "m", "element size"});
  s.params.push_back({"size_4_m", 0.7071e-3, "m", "finest element size"});
  s.params.push_back({"load_N", 20.0, "N", "contact force into the upper endplate of C5"});
  s.params.push_back({"patch_radius_m", 1.5e-3, "m", "radius of the contact's pressure patch"});
  s.params.push_back({"eval_radius_m", 3.0e-3, "m", "elements within this distance are measured"});
  s.params.push_back({"order", 1.0, "1", "element order: 1 linear, 2 quadratic tetrahedra"});
  s.params.push_back({"tolerance", 0.25, "1", "finest mesh against the extrapolated value"});
  return s;
}

std::vector<VerificationRow> run_bone_convergence(const VerificationCaseSpec& spec) {
  const SegmentParams segment;
  const SegmentLandmarks marks = segment_landmarks(segment);
  const TriangleMesh surface = generate_vertebra(segment, VertebraLevel::kC5);
  ContactLoad contact;
  contact.point_m = Vec3(0.0, marks.c5_upper_endplate_y_m, 0.0);
  contact.force_N = Vec3(0.0, -spec.get("load_N"), 0.0);
  contact.radius_m = spec.get("patch_radius_m");
  const double eval_radius = spec.get("eval_radius_m");
  const double tol = spec.get("tolerance");

  std::vector<Sample> samples;
  std::vector<VerificationRow> rows;
  for (const char* key : {"size_1_m", "size_2_m", "size_3_m", "size_4_m"}) {
    const double size = spec.get(key);
    if (!(size > 0.0)) continue;
    BoneFemConfig config;
    config.meshing.size_m = size;
    config.order = spec.get("order") >= 1.5 ? TetOrder::kQuadratic : TetOrder::kLinear;
    std::string error;
    auto bone = BoneFem::build(surface, segment, VertebraLevel::kC5, config, "", nullptr, &error);
    if (!bone) {
      VerificationRow row = make_row(spec, "mesh", std::nan(""), 0.0, tol);
      fail_row(row, error);
      return {row};
    }
    BoneSolution solution;
    bone->solve({&contact, 1}, solution);
    Sample s;
    s.nodes = bone->mesh().nodes.size();
    s.tets = bone->mesh().tets.size();
    s.target_m = size;
    s.size_m = std::cbrt(bone->mesh().volume() / static_cast<double>(s.tets));
    double volume = 0.0;
    for (std::size_t t = 0; t < s.tets; ++t) {
      if ((bone->mesh().centroid(t) - contact.point_m).norm() > eval_radius) continue;
      s.peak_Pa = std::max(s.peak_Pa, solution.element_von_mises_Pa[t]);
      if (bone->mesh().region[t] != static_cast<std::uint8_t>(BoneRegion::kCancellous)) continue;
      const double v = std::abs(bone->mesh().tet_volume(t));
      s.mean_Pa += v * solution.element_von_mises_Pa[t];
      volume += v;
    }
    s.mean_Pa = volume > 0.0 ? s.mean_Pa / volume : std::nan("");
    if (solution.contacts_missed > 0) {
      VerificationRow row = make_row(spec, "contact", std::nan(""), 0.0, tol);
      fail_row(row, "the contact point is not on the meshed surface");
      return {row};
    }
    samples.push_back(s);
  }
  if (samples.size() < 3) {
    VerificationRow row = make_row(spec, "meshes", static_cast<double>(samples.size()), 3.0, 0.0);
    fail_row(row, "three or more element sizes are needed");
    return {row};
  }

  const std::size_t n = samples.size();
  for (auto [f, name] :
       {std::pair{&Sample::peak_Pa, "peak"}, std::pair{&Sample::mean_Pa, "mean"}}) {
    double order = 0.0, extrapolated = 0.0;
    richardson(samples[n - 3], samples[n - 2], samples[n - 1], f, &order, &extrapolated);
    // The table: every mesh against the extrapolated value (the coarser ones for the trend).
    for (std::size_t i = 0; i < n; ++i) {
      char quantity[96], note[96];
      std::snprintf(quantity, sizeof quantity, "%s von Mises, %.2f mm mesh (MPa)", name,
                    samples[i].target_m * 1e3);
      std::snprintf(note, sizeof note, "%zu nodes, %zu tets, mean tet %.2f mm%s", samples[i].nodes,
                    samples[i].tets, samples[i].size_m * 1e3,
                    i + 1 < n ? "; coarser mesh, for the trend" : "");
      VerificationRow row = make_row(spec, quantity, samples[i].*f * 1e-6, extrapolated * 1e-6,
                                     i + 1 < n ? 1.0 : tol);
      if (row.note.empty()) row.note = note;
      rows.push_back(row);
    }
    // Converging: each refinement changes the value less than the one before.
    const double last = std::abs(samples[n - 1].*f - samples[n - 2].*f);
    const double before = std::abs(samples[n - 2].*f - samples[n - 3].*f);
    char quantity[96], note[96];
    std::snprintf(quantity, sizeof quantity, "%s: last change / change before", name);
    std::snprintf(note, sizeof note, "below 1 when converging; observed order %.2f", order);
    VerificationRow row = make_row(spec, quantity, before > 0.0 ? last / before : 0.0, 0.0, 1.0);
    row.passed = row.passed && row.simulated < 1.0;
    if (row.note.empty()) row.note = note;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace acdr::verification

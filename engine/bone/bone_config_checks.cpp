// The checks of the bone's configuration (meshing, elastic model, sampling and strengths), apart
// from the code that meshes and solves, so the scenario loader (and its fuzz target) can check a
// bone section without bringing in the mesher or the factorisation.
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/bone/bone_fem.hpp"
#include "engine/bone/bone_segment.hpp"
#include "engine/bone/tet_mesher.hpp"

namespace acdr {
namespace {

std::string mm_text(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%g mm", metres * 1e3);
  return text;
}

}  // namespace

std::string validate_tet_meshing_params(const TetMeshingParams& p) {
  std::string out;
  if (!(p.size_m > 0.0)) out += "size_m: got " + mm_text(p.size_m) + ", expected > 0\n";
  if (!(p.surface_distance_ratio > 0.0 && p.surface_distance_ratio <= 1.0))
    out += "surface_distance_ratio: got " + std::to_string(p.surface_distance_ratio) +
           ", expected 0 to 1\n";
  if (!(p.facet_angle_deg > 0.0 && p.facet_angle_deg <= 30.0))
    out += "facet_angle_deg: got " + std::to_string(p.facet_angle_deg) + ", expected 0 to 30\n";
  if (!(p.radius_edge_ratio >= 2.0))
    out += "radius_edge_ratio: got " + std::to_string(p.radius_edge_ratio) + ", expected >= 2\n";
  if (!(p.sliver_bound_deg >= 0.0 && p.sliver_bound_deg < 30.0))
    out += "sliver_bound_deg: got " + std::to_string(p.sliver_bound_deg) + ", expected 0 to 30\n";
  return out;
}

std::string validate_bone_fem_config(const BoneFemConfig& c) {
  std::string out = validate_tet_meshing_params(c.meshing);
  out += validate_bone_materials(c.materials);
  if (!(c.support_depth_m > 0.0))
    out +=
        "support_depth_m: got " + std::to_string(c.support_depth_m * 1e3) + " mm, expected > 0\n";
  if (!(c.max_snap_m > 0.0))
    out += "max_snap_m: got " + std::to_string(c.max_snap_m * 1e3) + " mm, expected > 0\n";
  return out;
}

std::string validate_bone_model_config(const BoneModelConfig& c) {
  std::string out = validate_bone_fem_config(c.fem);
  auto positive = [&](const char* key, double value, double scale, const char* unit) {
    if (!(value > 0.0) || !std::isfinite(value))
      out += std::string(key) + ": got " + std::to_string(value / scale) + " " + unit +
             ", expected > 0\n";
  };
  positive("sample_period_s", c.sample_period_s, 1.0, "s");
  positive("nucleus_cell_m", c.nucleus_cell_m, 1e-3, "mm");
  positive("endplate_strength_Pa", c.strengths.endplate_Pa, 1e6, "MPa");
  positive("posterior_strength_Pa", c.strengths.posterior_Pa, 1e6, "MPa");
  if (!(c.min_load_N >= 0.0))
    out += "min_load_N: got " + std::to_string(c.min_load_N) + " N, expected >= 0\n";
  if (!(c.strengths.warning_fraction > 0.0 && c.strengths.warning_fraction <= 1.0))
    out += "warning_fraction: got " + std::to_string(c.strengths.warning_fraction) +
           ", expected > 0 and <= 1\n";
  return out;
}

}  // namespace acdr

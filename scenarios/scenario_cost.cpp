// The cost model of a scenario (see scenario_cost.hpp). The per-item byte figures were measured:
// peak address space (VmPeak) of `acdr run --headless` over scenarios that vary one figure at
// a time (docs/scenario-format.md, Limits, gives the table).
#include "scenarios/scenario_cost.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/anatomy/anatomy.hpp"

namespace acdr {
namespace {

// Measured bytes per item (peak address space of a run, divided by the item count).
// Measured (VmPeak of `acdr run --headless` on a 0.1 s replay, this machine, Release):
//   the box module, no frames reserved                          225 MB
//   + 1,000,000 frames reserved (time limit 1000 s)            +473 MB  (472 B a frame)
//   15,000 / 42,500 / 183,000 particles, bond radius 1.5        +77 / +234 / +1146 MB
//   15,000 particles at bond radius 2.2 and 3 (+105k, +554k)    +8 / +50 MB  (76-90 B a bond)
//   C4-C5 module, 3.2 M grid samples built / 17.4 M (0.1 mm)    +40 / +194 MB  (11-13 B a sample)
// The figures below round these up.
constexpr double kBaseBytes = 250e6;          ///< the program, its libraries and threads
constexpr double kBytesPerParticle = 6000.0;  ///< particle state, neighbour rows, solver
constexpr double kBytesPerBond = 100.0;       ///< bond arrays and adjacency
constexpr double kBytesPerGridCell = 16.0;    ///< build scratch (distance, closest triangle) + values
constexpr double kBytesPerFrame = 700.0;      ///< the frame (472 B), its encoded copy and metrics
constexpr double kBytesPerMeshFileByte = 12.0;  ///< parsed and welded mesh, per byte of file
constexpr double kBytesPerMeshSample = 16.0;  ///< a generated vertebra's sample and its surface

/// Particles a block will hold on a lattice of spacing h: floor(size/h) + 1 per axis, and an
/// elliptic region fills at most pi/4 of its box.
double block_particles(const ParticleBlockConfig& b, double h) {
  double n = 1.0;
  for (int i = 0; i < 3; ++i) n *= std::floor(std::max(0.0, b.max_m[i] - b.min_m[i]) / h) + 1.0;
  if (b.shape == BlockShape::kEllipticCylinder) n *= 0.7854;
  return n;
}

/// Samples of one grid over [lo - margin, hi + margin] at spacing h, as the grid builder sizes it.
double grid_samples(const Vec3& lo, const Vec3& hi, double margin, double h) {
  if (!(h > 0.0)) return 0.0;
  double n = 1.0;
  for (int a = 0; a < 3; ++a) n *= std::ceil(std::max(0.0, hi[a] - lo[a] + 2.0 * margin) / h) + 1.0;
  return n;
}

double file_size(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? 0.0 : static_cast<double>(size);
}

}  // namespace

int lattice_neighbours_within(double factor) {
  const int m = static_cast<int>(std::ceil(factor));
  int count = 0;
  for (int a = -m; a <= m; ++a)
    for (int b = -m; b <= m; ++b)
      for (int c = -m; c <= m; ++c) {
        const double r = std::sqrt(double(a * a + b * b + c * c));
        if (r > 0.0 && r < factor) ++count;
      }
  return count;
}

ScenarioCost estimate_cost(const ScenarioModel& model) {
  ScenarioCost cost;
  const WorldConfig& w = model.world;
  if (w.nucleus.enabled && w.nucleus.spacing_m > 0.0) {
    for (const ParticleBlockConfig& b : w.nucleus.blocks) cost.particles += block_particles(b, w.nucleus.spacing_m);
    // Each bond joins two particles.
    cost.bonds = cost.particles * lattice_neighbours_within(w.nucleus.bond_radius_factor) / 2.0;
  }
  double mesh_file_bytes = 0.0;
  if (w.anatomy.enabled) {
    const AnatomyConfig& a = w.anatomy;
    Vec3 lo = a.sdf.clip_min_m, hi = a.sdf.clip_max_m;
    if (!a.sdf.clip) default_sdf_region(a.segment, &lo, &hi);
    // The bone grid for the particles, and one per vertebra for the zones, over the same region.
    cost.grid_cells = grid_samples(lo, hi, a.sdf.margin_m, a.sdf.spacing_m) +
                      2.0 * grid_samples(lo, hi, a.sdf.margin_m, a.zone_sdf_spacing_m);
    if (!a.c4_mesh_path.empty() && !a.c5_mesh_path.empty()) {
      mesh_file_bytes = file_size(a.c4_mesh_path) + file_size(a.c5_mesh_path);
    } else {
      // Generated vertebrae: each sampled on a grid of its own at the mesh spacing.
      cost.vertebra_samples = vertebra_grid_samples(a.segment, VertebraLevel::kC4) +
                     vertebra_grid_samples(a.segment, VertebraLevel::kC5);
      cost.grid_cells += cost.vertebra_samples;
    }
  }
  const double dt = w.solver.dt_s;
  cost.recording_frames = model.time_limit_s > 0.0 && dt > 0.0
                              ? std::ceil(model.time_limit_s / dt)
                              : ScenarioBudget::kRecordingFrames;
  cost.bytes = kBaseBytes + cost.particles * kBytesPerParticle + cost.bonds * kBytesPerBond +
               (cost.grid_cells - cost.vertebra_samples) * kBytesPerGridCell +
               cost.vertebra_samples * kBytesPerMeshSample +
               std::min(cost.recording_frames, ScenarioBudget::kRecordingFrames * 4.0) * kBytesPerFrame +
               mesh_file_bytes * kBytesPerMeshFileByte;
  return cost;
}

std::string cost_summary(const ScenarioCost& c) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "about %.0f particles, %.0f bonds, %.0f grid samples, %.0f frames, %s",
                c.particles, c.bonds, c.grid_cells, c.recording_frames, format_bytes(c.bytes).c_str());
  return buf;
}

std::string format_bytes(double bytes) {
  char buf[48];
  if (bytes >= 1e9) std::snprintf(buf, sizeof buf, "%.2f GB", bytes / 1e9);
  else if (bytes >= 1e6) std::snprintf(buf, sizeof buf, "%.0f MB", bytes / 1e6);
  else std::snprintf(buf, sizeof buf, "%.0f kB", bytes / 1e3);
  return buf;
}

}  // namespace acdr

// The particles' reaction on the bone gathered per cell (see the header).
#include "engine/world/particle_bone_cells.hpp"

#include <algorithm>
#include <limits>
#include <optional>

#include "engine/geometry/signed_distance_grid.hpp"

namespace acdr {
namespace {

// The cell among [0, count) of `vertebra` whose weighted centre is nearest p, or -1.
int nearest_cell(const ParticleBoneCells& c, int count, std::uint8_t vertebra, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  int slot = -1;
  for (int k = 0; k < count; ++k) {
    if (c.vertebra[k] != vertebra || c.weight[k] <= 0.0) continue;
    const double d = (c.sum[k] / c.weight[k] - p).squaredNorm();
    if (d < best) best = d, slot = k;
  }
  return slot;
}

}  // namespace

void ParticleBoneCells::gather(std::span<const Vec3> forces, std::span<const Vec3> x,
                               const SignedDistanceGrid& c4, const SignedDistanceGrid& c5,
                               double cell, int capacity) {
  count = 0;
  cell_m = cell;
  capacity = std::clamp(capacity, 0, kCapacity);
  for (std::size_t i = 0; i < forces.size(); ++i) {
    const Vec3& f = forces[i];
    const double w = f.norm();
    if (!(w > 0.0)) continue;
    const std::uint8_t v = c4.distance(x[i]) <= c5.distance(x[i]) ? 0 : 1;
    const Eigen::Array3d c = (x[i] / cell).array().floor();
    // Cells within +-2^20 of the origin (2 km at 2 mm): a unique key per cell and vertebra.
    const std::int64_t cell_key = ((static_cast<std::int64_t>(c.x()) + (1 << 20)) << 42) |
                                  ((static_cast<std::int64_t>(c.y()) + (1 << 20)) << 21) |
                                  (static_cast<std::int64_t>(c.z()) + (1 << 20));
    const std::int64_t full_key = cell_key * 2 + v;
    int slot = 0;
    while (slot < count && key[slot] != full_key) ++slot;
    if (slot == count) {
      if (count >= capacity) {
        slot = nearest_cell(*this, count, v, x[i]);
        if (slot < 0) continue;
      } else {
        key[count] = full_key;
        vertebra[count] = v;
        weight[count] = 0.0;
        sum[count] = Vec3::Zero();
        force[count] = Vec3::Zero();
        ++count;
      }
    }
    force[slot] += f;
    sum[slot] += w * x[i];
    weight[slot] += w;
  }
}

void ParticleBoneCells::append_to(BoneLoadSample& out) const {
  const int room = std::max(0, BoneLoadSample::kCapacity - out.count);
  const ParticleBoneCells* cells = this;
  std::optional<ParticleBoneCells> merged;  // made only when the cells do not fit
  if (count > room) {
    // Too many: the cells beyond the room join the nearest kept cell of their vertebra.
    merged.emplace(*this);
    merged->count = room;
    for (int k = room; k < count; ++k) {
      const int slot = nearest_cell(*merged, room, vertebra[k], sum[k] / weight[k]);
      if (slot < 0) continue;
      merged->force[slot] += force[k];
      merged->sum[slot] += sum[k];
      merged->weight[slot] += weight[k];
    }
    cells = &*merged;
  }
  for (int k = 0; k < cells->count; ++k) {
    BoneLoadPoint& p = out.points[out.count++];
    p.radius_m = static_cast<float>(0.5 * cell_m);
    p.vertebra = cells->vertebra[k];
    p.source = BoneLoadSource::kNucleus;
    p.point_m = (cells->sum[k] / cells->weight[k]).cast<float>();
    p.force_N = cells->force[k].cast<float>();
  }
}

}  // namespace acdr

// Lumps of removed material: the removed particles at the end of an attempt, joined into
// clusters where their centres lie closer than a link distance (single linkage). A gel taken
// out with a curette leaves in lumps; particles that scatter one by one look and behave like
// sand. Definitions in docs/assessment.md.
#pragma once

#include <span>

#include <Eigen/Core>

namespace acdr {

/// A cluster of at least this many particles counts as a lump.
inline constexpr int kLumpMinParticles = 10;
/// Two removed particles belong to the same cluster when their centres are closer than this
/// many lattice spacings: the radius within which the lattice bonds neighbours at the start
/// (bond_radius_factor's default), so an undisturbed piece of the lattice is one cluster.
inline constexpr double kLumpLinkSpacings = 1.5;

struct LumpStats {
  int particles = 0;  ///< removed particles
  int clusters = 0;   ///< connected clusters, single particles included
  int lumps = 0;      ///< clusters of at least the lump size
  int in_lumps = 0;   ///< particles in those
  int largest = 0;    ///< particles in the largest cluster

  /// Share of the removed particles that are in lumps (0 when nothing was removed).
  double lump_fraction() const { return particles > 0 ? double(in_lumps) / particles : 0.0; }
};

/// Clusters of `positions` (m) under single linkage at `link_m`. Deterministic; O(n) with a
/// cell grid of side `link_m`.
LumpStats removed_lumps(std::span<const Eigen::Vector3f> positions, double link_m,
                        int min_particles = kLumpMinParticles);

}  // namespace acdr

// The per-material surface cache.
#include "ui/material_surfaces.hpp"

#include "engine/core/state_hash.hpp"

namespace acdr {

const ParticleSurface& MaterialSurfaceCache::surface(std::uint64_t key,
                                                     std::span<const Eigen::Vector3f> centres,
                                                     float spacing_m, bool* reused) {
  std::uint64_t h = fnv1a(centres.data(), centres.size_bytes());
  h = fnv1a(&spacing_m, sizeof spacing_m, h);
  h |= 1u;  // never 0, which means "none"
  Entry& e = entries_[key];
  const bool same = e.hash == h;
  if (!same) {
    e.surface = particle_surface(centres, spacing_m);
    e.hash = h;
    ++extractions_;
  }
  if (reused) *reused = same;
  return e.surface;
}

std::uint64_t MaterialSurfaceCache::hash(std::uint64_t key) const {
  const auto it = entries_.find(key);
  return it == entries_.end() ? 0 : it->second.hash;
}

}  // namespace acdr

// The particle materials drawn as material: one smooth surface per material in place
// (nucleus, annulus, cartilage) and one over the removed material, each with the finish that
// reads as that tissue, or, as a debug view, the particles as beads.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>

#include "ui/particle_surface.hpp"

namespace acdr {

/// How particle materials are drawn. Beads show each particle as a sphere: a debug view of
/// what the solver moves (`acdr run --beads`, `acdr render --beads`, key B in the window).
enum class MaterialDrawing : std::uint8_t { kSurfaces, kBeads };

/// Keeps each material's surface between frames of a live view, so a surface is extracted
/// again only when its particles moved (resting annulus and cartilage cost nothing).
class MaterialSurfaceCache {
 public:
  /// The surface over `centres` for the material `key`; from the cache when the centres are
  /// bit for bit those of the previous call with this key (`*reused` then true).
  const ParticleSurface& surface(std::uint64_t key, std::span<const Eigen::Vector3f> centres,
                                 float spacing_m, bool* reused = nullptr);
  /// Content hash of the centres the cached surface of `key` was made from (0: none).
  std::uint64_t hash(std::uint64_t key) const;
  /// Surfaces extracted since the cache was made (for measuring the live cost).
  std::uint64_t extractions() const { return extractions_; }

 private:
  struct Entry {
    std::uint64_t hash = 0;
    ParticleSurface surface;
  };
  std::unordered_map<std::uint64_t, Entry> entries_;
  std::uint64_t extractions_ = 0;
};

}  // namespace acdr

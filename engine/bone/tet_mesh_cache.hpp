// Volume meshes through the disk cache, like the distance grids: keyed by the surface's
// content hash, the meshing parameters and the mesher's version, so a second start with the
// same bone loads the mesh (milliseconds) instead of meshing it again (seconds).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "engine/bone/tet_mesher.hpp"

namespace acdr {

/// The cache key of a surface meshed with `params`.
std::uint64_t tet_mesh_cache_key(const TriangleMesh& surface, const TetMeshingParams& params);

/// What loading or meshing did.
struct TetMeshLoadInfo {
  bool from_cache = false;
  double seconds = 0.0;  ///< meshing, or reading the cache file
  TetQuality quality;
  std::string note;  ///< a cache file that could not be read or written, if any
};

/// The mesh of `surface`: from `cache_dir` when meshed before with the same parameters (and the
/// loaded mesh meets the quality limits), else meshed and stored. An empty `cache_dir` always meshes. A surface that cannot be meshed
/// gives nullopt and the mesher's error (nothing is cached).
std::optional<TetMesh> load_or_mesh_surface(const TriangleMesh& surface,
                                            const TetMeshingParams& params,
                                            const std::string& cache_dir, TetMeshLoadInfo* info,
                                            std::string* error);

}  // namespace acdr

// Cached volume meshing.
#include "engine/bone/tet_mesh_cache.hpp"

#include <chrono>

#include "engine/core/disk_cache.hpp"
#include "engine/core/state_hash.hpp"

namespace acdr {
namespace {

// Bump whenever the meshing code changes what it produces: cached meshes are keyed by it.
constexpr std::uint32_t kMesherVersion = 1;

}  // namespace

std::uint64_t tet_mesh_cache_key(const TriangleMesh& surface, const TetMeshingParams& params) {
  // The parameter struct holds doubles only, so its bytes are its values.
  static_assert(sizeof(TetMeshingParams) % sizeof(double) == 0);
  const std::uint64_t surface_hash = surface.content_hash();
  std::uint64_t key = fnv1a(&kMesherVersion, sizeof kMesherVersion);
  key = fnv1a(&surface_hash, sizeof surface_hash, key);
  return fnv1a(&params, sizeof params, key);
}

std::optional<TetMesh> load_or_mesh_surface(const TriangleMesh& surface,
                                            const TetMeshingParams& params,
                                            const std::string& cache_dir, TetMeshLoadInfo* info,
                                            std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  TetMeshLoadInfo local;
  TetMeshLoadInfo& out = info ? *info : local;
  out = {};
  const std::string path =
      cache_dir.empty() ? ""
                        : cache_file_path(cache_dir, tet_mesh_cache_key(surface, params), ".tet");
  if (!path.empty()) {
    if (const auto bytes = read_cache_file(path)) {
      std::string why;
      auto mesh = TetMesh::deserialize(*bytes, &why);
      // Every mesh is checked, a cached one too: a file could hold anything.
      if (mesh) {
        out.quality = tet_quality(*mesh);
        why = check_tet_quality(out.quality, params.limits);
      }
      if (mesh && why.empty()) {
        out.from_cache = true;
        out.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return mesh;
      }
      out.note = path + ": " + why + " (meshed again)";
    }
  }
  TetMeshingResult result = mesh_closed_surface(surface, params);
  out.quality = result.quality;
  out.seconds = result.seconds;
  if (!result.mesh) {
    if (error) *error = result.error;
    return std::nullopt;
  }
  std::string why;
  if (!path.empty() && !write_cache_file(path, result.mesh->serialize(), &why))
    out.note += (out.note.empty() ? "" : "; ") + path + ": not cached: " + why;
  return std::move(result.mesh);
}

}  // namespace acdr

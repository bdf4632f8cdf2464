// The anatomical scene a World is built with when its scenario declares anatomy: the C4 and C5
// meshes (generated or loaded), the bone's signed distance grids, and the danger zones. Built
// once, before the rigid world and the nucleus; immutable afterwards. Slow parts (meshing,
// grids) go through the disk cache, and what they cost is reported.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "engine/geometry/collider.hpp"
#include "engine/anatomy/danger_zone.hpp"
#include "engine/geometry/signed_distance_grid.hpp"
#include "engine/geometry/triangle_mesh.hpp"
#include "engine/anatomy/vertebra_generator.hpp"
#include "engine/anatomy/anatomy_config.hpp"

namespace acdr {

/// What building the anatomy took (for start-up reports and the benchmark).
struct AnatomyBuildReport {
  double mesh_seconds = 0.0;      ///< generating or loading both vertebrae
  bool meshes_from_cache = false; ///< both generated meshes came from the cache
  bool meshes_from_files = false;
  std::size_t triangles = 0;      ///< both vertebrae
  double sdf_seconds = 0.0;       ///< all grids, built or loaded
  bool sdf_from_cache = false;    ///< every grid came from the cache
  std::array<int, 3> sdf_dims{0, 0, 0};  ///< particle-contact grid
  std::string notes;              ///< cache problems, if any
};

class Anatomy {
 public:
  /// Builds everything `config` declares. Throws std::runtime_error naming the file and the
  /// problem when a mesh file cannot be used (the scenario loader checks files first with
  /// `check_anatomy_files`, so a validated scenario does not throw).
  explicit Anatomy(const AnatomyConfig& config);

  const AnatomyConfig& config() const { return config_; }
  const SegmentLandmarks& landmarks() const { return landmarks_; }
  const TriangleMesh& vertebra(VertebraLevel level) const {
    return meshes_[level == VertebraLevel::kC4 ? 0 : 1];
  }
  /// Both vertebrae: the particles' contact grid (one lookup per particle).
  const SignedDistanceGrid& bone_grid() const { return bone_grid_; }
  /// Each vertebra alone (endplate zones).
  const SignedDistanceGrid& vertebra_grid(VertebraLevel level) const {
    return vertebra_grids_[level == VertebraLevel::kC4 ? 0 : 1];
  }
  /// The static collider the particles see for the bone.
  Collider bone_collider() const;
  /// The posterior longitudinal ligament the particles see: a flat wall across the canal's
  /// width and the disc's height, its front face `face_offset_m` behind the bodies' posterior
  /// wall, 3 mm thick; `particles_only` (a blade passes it). See docs/anatomy.md.
  Collider posterior_ligament_collider(double face_offset_m) const;
  /// Generated zones first, then the scenario's own, in a fixed order (at most kMaxZones).
  const std::vector<DangerZone>& zones() const { return zones_; }
  const AnatomyBuildReport& report() const { return report_; }

  Anatomy(const Anatomy&) = delete;
  Anatomy& operator=(const Anatomy&) = delete;

 private:
  AnatomyConfig config_;
  SegmentLandmarks landmarks_;
  std::array<TriangleMesh, 2> meshes_;
  SignedDistanceGrid bone_grid_;
  std::array<SignedDistanceGrid, 2> vertebra_grids_;
  std::vector<DangerZone> zones_;
  AnatomyBuildReport report_;
};

/// The region the particle-contact grid covers by default: the disc space and 3-4 mm around.
void default_sdf_region(const SegmentParams& params, Vec3* min_m, Vec3* max_m);

/// Checks that the mesh files `config` names load as closed surfaces; "" when fine (or when no
/// files are named), else "path: what is wrong" (one line per file).
std::string check_anatomy_files(const AnatomyConfig& config);

/// C4 and C5 as the scene uses them: loaded from the files `config` names, or generated from its
/// morphometry through the mesh cache (`from_cache`: both came from it). Throws
/// std::runtime_error when a file cannot be used.
std::array<TriangleMesh, 2> load_vertebra_meshes(const AnatomyConfig& config, bool* from_cache = nullptr);

/// The cache directory `config.cache_dir` means ("" when caching is off).
std::string anatomy_cache_dir(const AnatomyConfig& config, const std::string& sub);

}  // namespace acdr

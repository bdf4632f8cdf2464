// Building the anatomical scene: meshes, grids and zones, through the disk cache.
#include "engine/anatomy/anatomy.hpp"

#include <chrono>
#include <stdexcept>

#include "engine/core/disk_cache.hpp"
#include "engine/geometry/mesh_io.hpp"

namespace acdr {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

LengthUnit unit_of(double metres_per_unit) {
  return metres_per_unit == 1.0 ? LengthUnit::kMetre : LengthUnit::kMillimetre;
}

}  // namespace

std::string anatomy_cache_dir(const AnatomyConfig& config, const std::string& sub) {
  if (config.cache_dir == "none") return "";
  if (config.cache_dir.empty()) return default_cache_dir(sub);
  return config.cache_dir + "/" + sub;
}

void default_sdf_region(const SegmentParams& p, Vec3* min_m, Vec3* max_m) {
  const SegmentLandmarks l = segment_landmarks(p);
  *min_m = Vec3(-l.body_half_width_m - 3e-3, l.c5_upper_endplate_y_m - 4e-3, l.body_back_z_m - 4e-3);
  *max_m = Vec3(l.body_half_width_m + 3e-3, l.c4_lower_endplate_y_m + 4e-3, l.body_front_z_m + 3e-3);
}

std::string check_anatomy_files(const AnatomyConfig& config) {
  std::string out;
  for (const std::string& path : {config.c4_mesh_path, config.c5_mesh_path}) {
    if (path.empty()) continue;
    std::string error;
    if (!load_closed_mesh_file(path, unit_of(config.mesh_unit_m), &error)) out += error + "\n";
  }
  return out;
}

std::array<TriangleMesh, 2> load_vertebra_meshes(const AnatomyConfig& config, bool* from_cache) {
  std::array<TriangleMesh, 2> meshes;
  const bool files = !config.c4_mesh_path.empty() && !config.c5_mesh_path.empty();
  const std::string mesh_cache = anatomy_cache_dir(config, "mesh");
  bool all_cached = true;
  for (int i = 0; i < 2; ++i) {
    const VertebraLevel level = i == 0 ? VertebraLevel::kC4 : VertebraLevel::kC5;
    if (files) {
      std::string error;
      const std::string& path = i == 0 ? config.c4_mesh_path : config.c5_mesh_path;
      auto mesh = load_closed_mesh_file(path, unit_of(config.mesh_unit_m), &error);
      if (!mesh) throw std::runtime_error(error);
      meshes[i] = std::move(*mesh);
    } else {
      bool cached = false;
      meshes[i] = load_or_generate_vertebra(config.segment, level, mesh_cache, nullptr, &cached);
      all_cached = all_cached && cached;
    }
  }
  if (from_cache) *from_cache = !files && all_cached;
  return meshes;
}

Anatomy::Anatomy(const AnatomyConfig& config) : config_(config) {
  landmarks_ = segment_landmarks(config.segment);

  // Vertebrae: loaded from files, or generated (cached by their parameters).
  auto t0 = std::chrono::steady_clock::now();
  const bool files = !config.c4_mesh_path.empty() && !config.c5_mesh_path.empty();
  report_.meshes_from_files = files;
  bool cached = false;
  meshes_ = load_vertebra_meshes(config, &cached);
  report_.meshes_from_cache = !files && cached;
  report_.triangles = meshes_[0].triangle_count() + meshes_[1].triangle_count();
  report_.mesh_seconds = seconds_since(t0);

  // Grids: both vertebrae for the particles; each alone, coarser, for the endplate zones.
  t0 = std::chrono::steady_clock::now();
  const std::string sdf_cache = anatomy_cache_dir(config, "sdf");
  SdfGridParams bone_params = config.sdf;
  if (!bone_params.clip) {
    bone_params.clip = true;
    default_sdf_region(config.segment, &bone_params.clip_min_m, &bone_params.clip_max_m);
  }
  TriangleMesh both = meshes_[0];
  both.append(meshes_[1]);
  SdfLoadInfo info;
  bone_grid_ = build_or_load_sdf(both, bone_params, sdf_cache, &info);
  report_.sdf_from_cache = info.from_cache;
  if (!info.note.empty()) report_.notes += info.note + "\n";
  report_.sdf_dims = bone_grid_.dims();
  SdfGridParams zone_params = bone_params;
  zone_params.spacing_m = config.zone_sdf_spacing_m;
  for (int i = 0; i < 2; ++i) {
    vertebra_grids_[i] = build_or_load_sdf(meshes_[i], zone_params, sdf_cache, &info);
    report_.sdf_from_cache = report_.sdf_from_cache && info.from_cache;
    if (!info.note.empty()) report_.notes += info.note + "\n";
  }
  report_.sdf_seconds = seconds_since(t0);

  // Zones: generated, then declared; band zones point at their vertebra's grid.
  if (config.generate_zones) {
    zones_ = make_c4c5_zones(config.segment, landmarks_, &vertebra_grids_[0], &vertebra_grids_[1],
                             config.zone_params);
  }
  for (DangerZone z : config.extra_zones) {
    if (z.shape == ZoneShape::kSdfBand) z.sdf = &vertebra_grids_[z.bone == 0 ? 0 : 1];
    zones_.push_back(z);
  }
  if (zones_.size() > static_cast<std::size_t>(kMaxZones)) zones_.resize(kMaxZones);
}

Collider Anatomy::bone_collider() const {
  Collider c;
  c.kind = ColliderKind::kSdfGrid;
  c.sdf = &bone_grid_;
  return c;
}

Collider Anatomy::posterior_ligament_collider(double face_offset_m) const {
  const SegmentLandmarks& l = landmarks_;
  constexpr double kThickness = 3.0e-3;  // deeper than a particle's reach: one flat face
  Collider c;
  c.kind = ColliderKind::kBox;
  c.particles_only = true;
  const double face_z = l.body_back_z_m - face_offset_m;
  c.pose.position = Vec3(0.0, 0.5 * (l.c4_lower_endplate_y_m + l.c5_upper_endplate_y_m),
                         face_z - 0.5 * kThickness);
  c.half_extents_m = Vec3(l.canal_half_width_m,
                          0.5 * (l.c4_lower_endplate_y_m - l.c5_upper_endplate_y_m),
                          0.5 * kThickness);
  return c;
}

}  // namespace acdr

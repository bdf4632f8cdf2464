// Procedural cervical vertebrae (C4 and C5) as closed, watertight triangle meshes built from
// published morphometry, and the landmarks that place the danger zones around them.
//
// Each vertebra is a union of simple solids (body, uncinate processes, pedicles, transverse
// processes around the foramen transversarium, lateral masses with facet joints, laminae,
// bifid spinous process) blended into one implicit solid, sampled on a grid and meshed by
// marching tetrahedra (engine/geometry/iso_surface.hpp). Recognisable anatomy, not fine detail.
//
// Segment frame (docs/anatomy.md), SI metres, origin at the centre of the C4-C5 disc space:
//   x  patient's left (lateral), y  cranial (along the spine, C4 above), z  anterior.
// The patient lies supine for an anterior cervical approach, so z (anterior) points up at
// the ceiling: gravity is -z, and the instrument comes from above (+z) with its shaft along
// -z, exactly the convention of the box module, the trajectories and the renderer.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "engine/geometry/triangle_mesh.hpp"

namespace acdr {

/// Morphometry of one cervical vertebra (SI). Defaults: C4 from docs/references.md "Cervical
/// geometry"; values marked "default" were not found published and are scenario-editable.
struct VertebraParams {
  /// Width of the disc-bearing endplate between the medial uncinate margins: disc width
  /// 16.13 +- 1.99 mm, C3-C7 pooled CT (Frontiers Bioeng 2022, doi 10.3389/fbioe.2022.1036223).
  double endplate_width_m = 16.1e-3;
  /// Antero-posterior depth of the body: disc AP depth 16.08 +- 1.84 mm (same); body mid-AP
  /// diameter 14.7 (C3) to 16.1 mm (C7) (Lu et al. 1998).
  double body_depth_m = 16.1e-3;
  /// Height of the body between its endplates. Default 14 mm (cervical bodies ~13-15 mm).
  double body_height_m = 14.0e-3;
  /// Uncinate process height above the upper endplate: 5.8-6.1 mm at C4-C6 (Lu et al. 1998).
  double uncinate_height_m = 5.9e-3;
  /// Uncinate process thickness at its base. Default 2.5 mm.
  double uncinate_thickness_m = 2.5e-3;
  /// Fraction of the body depth, from the back, that carries the uncinate process. Default 0.6.
  double uncinate_depth_fraction = 0.6;
  /// Pedicle width 4.99-6.26 mm across C3-C7 (Sayin, J Turk Spinal Surg 2021).
  double pedicle_width_m = 5.5e-3;
  /// Pedicle height. Default 7 mm.
  double pedicle_height_m = 7.0e-3;
  /// Spinal canal at C4: sagittal 12.77 +- 1.48 mm, transverse 20.37 +- 1.72 mm (Parihar).
  double canal_sagittal_m = 12.8e-3;
  double canal_transverse_m = 20.4e-3;
  /// Foramen transversarium diameter: 5.55 +- 0.87 (R), 5.48 +- 0.77 mm (L) (Anat Res Int 2015).
  double foramen_transversarium_diameter_m = 5.5e-3;
  /// Medial uncinate margin to the medial edge of the foramen transversarium: 5.0 +- 0.87 mm
  /// (same source).
  double uncinate_to_foramen_m = 5.0e-3;
  /// Centre of the foramen transversarium ahead of the posterior body wall. Default 3 mm.
  double foramen_anterior_offset_m = 3.0e-3;
  /// Transverse process reach beyond the lateral edge of the foramen. Default 4.5 mm.
  double transverse_process_reach_m = 4.5e-3;
  /// Lamina thickness. Default 2.5 mm.
  double lamina_thickness_m = 2.5e-3;
  /// Spinous process length behind the laminae. Default 11 mm.
  double spinous_process_length_m = 11.0e-3;
  /// How far the superior endplate rises from its middle to the base of the uncinate processes
  /// (the transverse concavity of the saddle). Superior cervical endplate concavity depth
  /// 0.9-1.2 mm, C3-C7 CT of 97 adults (Chen et al., Eur Spine J 2013;22(7):1570-5, mid-sagittal);
  /// default 1.0 mm.
  double superior_concavity_m = 1.0e-3;
  /// How far the anterior lip of the inferior endplate hangs below the endplate. Inferior
  /// endplates are the more concave, 2.1-2.7 mm (same source), the anterior lip making much of
  /// it; default 1.5 mm.
  double anterior_lip_m = 1.5e-3;
  /// Width of the anterior lip taken off over the middle, as the surgeon does with a rongeur to
  /// open the view into the disc space before the discectomy. Default 0: an intact lip.
  double lip_resection_width_m = 0.0;
};

/// The C4-C5 motion segment: two vertebrae and the disc space between them.
struct SegmentParams {
  VertebraParams c4;
  VertebraParams c5;
  /// C4-5 disc height: 5.99 +- 0.94 mm (men), 5.77 +- 0.88 mm (women), MRI (Koken 2014).
  double disc_height_m = 5.9e-3;
  /// Facet (zygapophyseal) joint gap between the lateral masses. Default 1 mm.
  double facet_gap_m = 1.0e-3;
  /// Grid spacing of the mesh generator: sets the detail and the triangle count.
  double mesh_spacing_m = 0.5e-3;
};

enum class VertebraLevel { kC4, kC5 };
const char* vertebra_level_name(VertebraLevel level);

/// Places the danger zones and the disc space regions; all in the segment frame (m).
/// Index 0 is the +x (patient's left) side, 1 the -x (right) side.
struct SegmentLandmarks {
  double c4_lower_endplate_y_m = 0.0;   ///< +disc/2
  double c5_upper_endplate_y_m = 0.0;   ///< -disc/2
  double endplate_half_width_m = 0.0;   ///< medial uncinate margin, |x|
  double body_half_width_m = 0.0;       ///< lateral body wall, |x|
  double body_front_z_m = 0.0;          ///< anterior body wall
  double body_back_z_m = 0.0;           ///< posterior body wall (front of the canal)
  double uncinate_front_z_m = 0.0;      ///< the uncinate processes span z in [back, front]
  double canal_back_z_m = 0.0;          ///< back of the canal (front of the laminae)
  double canal_half_width_m = 0.0;
  std::array<Vec3, 2> foramen_transversarium_m{};  ///< centre at the disc mid-level
  double foramen_radius_m = 0.0;
  /// Exiting nerve root (C5 at C4-5): from the dura through the intervertebral foramen,
  /// passing behind the vertebral artery; three points per side.
  std::array<std::array<Vec3, 3>, 2> nerve_root_m{};
  std::array<Vec3, 2> uncinate_posterior_tip_m{};  ///< C5's uncinate tips, posterior end
};

SegmentLandmarks segment_landmarks(const SegmentParams& params);

/// A named part of the segment and a point on it (segment frame, m): where a picture puts its
/// label. `bone` is 0 for C4, 1 for C5, -1 for soft tissue (disc, vessels, nerves).
struct PartPoint {
  std::string name;
  Vec3 point_m = Vec3::Zero();
  int bone = -1;
};

/// The parts a surgeon names, each with a point just inside it: C4 and C5 bodies, the superior
/// endplate's saddle, the uncinate processes, the anterior lip, pedicles, transverse processes
/// with their anterior and posterior tubercles, the foramina transversaria, lateral masses with
/// their facet joint, laminae, the bifid spinous process, the spinal canal. Paired parts are
/// given on one side: `side` -1 the patient's right (-x), +1 the left (+x).
std::vector<PartPoint> segment_part_points(const SegmentParams& params, double side = -1.0);

/// Centre of a vertebra's body in the segment frame: y = +-(disc + height) / 2.
Vec3 vertebra_center(const SegmentParams& params, VertebraLevel level);

/// Implicit solid of one vertebra in the segment frame (m, negative inside; a bound on the
/// distance, not exact).
double vertebra_implicit(const SegmentParams& params, VertebraLevel level, const Vec3& p);

/// What generating a vertebra took and gave.
struct VertebraMeshStats {
  double seconds = 0.0;
  std::size_t samples = 0;
  std::size_t triangles = 0;
  double volume_m3 = 0.0;
};

/// Samples of the grid `generate_vertebra` evaluates the implicit solid on (its memory and
/// time grow with this), from the parameters alone.
double vertebra_grid_samples(const SegmentParams& params, VertebraLevel level);

/// Meshes one vertebra in the segment frame. The mesh passes `check_closed_mesh`.
TriangleMesh generate_vertebra(const SegmentParams& params, VertebraLevel level,
                               VertebraMeshStats* stats = nullptr);

/// Same mesh, through the disk cache: loaded from `cache_dir` when generated before with the
/// same parameters (key: FNV-1a of the parameters and the shape version), else generated and
/// stored. An empty `cache_dir` always generates. `stats->seconds` is the time either took.
TriangleMesh load_or_generate_vertebra(const SegmentParams& params, VertebraLevel level,
                                       const std::string& cache_dir, VertebraMeshStats* stats = nullptr,
                                       bool* from_cache = nullptr);

/// Checks the parameters (positive sizes, the disc fitting between the uncinate processes,
/// the foramen clear of the body...). Empty when fine, else "c4.endplate_width_m: ..." lines.
std::string validate_segment_params(const SegmentParams& params);

}  // namespace acdr

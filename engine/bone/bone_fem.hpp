// One vertebra as a linear elastic finite-element model, ready for loads: its volume mesh
// (cached), regions and materials, supports, and the stiffness factorised once. A load update
// (contacts on the surface) is one solve plus the stresses, a few milliseconds.
//
// Supports, for a C4-C5 segment lying supine on the table in the anterior approach: each
// vertebra is held where it meets the spine outside the segment, its far side. Every surface
// node within `support_depth_m` of the far endplate plane is fixed: C4's upper endplate (on
// the C3-C4 disc) with its uncinate processes and superior facets (the uncovertebral and facet
// joints with C3), C5's lower endplate (on the C5-C6 disc) with its inferior facets. The near
// side, the C4-C5 disc space where the instrument works, is free. This is the usual boundary
// condition of vertebral finite-element models (the lowest endplate fixed) applied to each
// vertebra; the posterior soft tissue on the table is not a support (docs/bone-fem.md).
//
// Threads: a built BoneFem is immutable. `solve` is const, reads only the model and writes only
// the caller's BoneSolution, so a solver thread can own the calls while the builder does other
// work; two threads may even solve at once, each with its own solution.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/anatomy/vertebra_generator.hpp"
#include "engine/bone/bone_material.hpp"
#include "engine/bone/bone_regions.hpp"
#include "engine/bone/boundary_surface.hpp"
#include "engine/bone/elastic_model.hpp"
#include "engine/bone/surface_load.hpp"
#include "engine/bone/tet_mesh_cache.hpp"

namespace acdr {

/// How a vertebra is modelled (SI; scenario-editable).
struct BoneFemConfig {
  TetMeshingParams meshing;            ///< default 1.5 mm elements (docs/bone-fem.md)
  TetOrder order = TetOrder::kLinear;  ///< chosen by the verification (docs/bone-fem.md)
  SparseSolverKind solver = SparseSolverKind::kCholmod;  ///< chosen by measurement (same)
  BoneMaterials materials;
  /// Surface nodes within this distance of the far endplate plane are fixed (m).
  double support_depth_m = 1.0e-3;
  /// A contact farther than this from the surface is not applied (counted as missed) (m).
  double max_snap_m = 2.0e-3;
};

/// "" when the configuration is usable, else one "key: got ..., expected ..." line per problem.
std::string validate_bone_fem_config(const BoneFemConfig& config);

/// What building took.
struct BoneFemReport {
  TetMeshLoadInfo mesh;                                     ///< meshing or cache load
  double classify_seconds = 0.0;                            ///< surface, depths, regions
  ElasticBuildReport elastic;                               ///< assembly and factorisation
  std::array<std::size_t, kBoneRegionCount> region_tets{};  ///< per BoneRegion
  std::size_t supported_nodes = 0;
  double total_seconds = 0.0;
};

/// The result of one load: per node and per element fields, and what was applied.
struct BoneSolution {
  std::vector<Vec3> displacement_m;  ///< per mesh node (corner)
  /// Per tetrahedron, at its centroid; in shell tetrahedra the stress in the shell itself
  /// (cortex or bony endplate) at the element's strain (bone_material.hpp, stress_material).
  /// Principal stresses cost more than the rest of the recovery (trigonometry); callers take
  /// them where they need them with principal_stresses(element_stress_Pa[t]).
  std::vector<Stress6> element_stress_Pa;
  std::vector<double> element_von_mises_Pa;
  std::vector<double> node_von_mises_Pa;  ///< per mesh node, volume-weighted average (drawing)
  int contacts_applied = 0;
  int contacts_missed = 0;              ///< farther than max_snap_m from the surface
  Vec3 applied_force_N = Vec3::Zero();  ///< sum of the applied contact forces
  double solve_seconds = 0.0;           ///< forces, substitution (wall)
  double stress_seconds = 0.0;          ///< stress recovery (wall)
  // Scratch reused between solves (3 per FE node).
  std::vector<double> force_N, dof_displacement_m;
  std::vector<Stress6> node_stress_Pa;
  std::vector<std::uint32_t> faces;
  ElasticSolveWorkspace workspace;
};

class BoneFem {
 public:
  /// Meshes (or loads from `cache_dir`; "" = no cache) the closed `surface` of a vertebra at
  /// `level` of the segment `params`, labels regions, fixes the far side and factorises.
  /// Returns nullptr with `error` set for a surface that cannot be meshed or a bad config.
  static std::unique_ptr<BoneFem> build(const TriangleMesh& surface, const SegmentParams& params,
                                        VertebraLevel level, const BoneFemConfig& config,
                                        const std::string& cache_dir, BoneFemReport* report,
                                        std::string* error);

  /// Solves for the contacts (forces on the bone, N; positions on its surface, m). Without
  /// `nodal_fields` the per-node stresses (for drawing) are left out and node_von_mises_Pa is
  /// emptied: what the metrics need costs less. With `partial` (from
  /// model().partial_solve_for) only its elements' stresses are computed, and only the
  /// displacements they need: the other entries of displacement_m, element_stress_Pa and
  /// element_von_mises_Pa are NaN, and nodal_fields is ignored. The computed ones equal a full
  /// solve's bit for bit.
  void solve(std::span<const ContactLoad> contacts, BoneSolution& out, bool nodal_fields = true,
             const PartialSolve* partial = nullptr) const;

  const TetMesh& mesh() const { return mesh_; }  ///< regions set
  const BoneRegionLabels& labels() const { return labels_; }
  const BoundarySurface& surface() const { return *surface_; }
  const ElasticModel& model() const { return *model_; }
  const BoneFemConfig& config() const { return config_; }
  const VertebraBodyFrame& body() const { return body_; }
  VertebraLevel level() const { return level_; }
  /// Fixed-axis mask per mesh node (kFixAll on the supports).
  const std::vector<std::uint8_t>& supports() const { return fixed_; }

  BoneFem(const BoneFem&) = delete;
  BoneFem& operator=(const BoneFem&) = delete;

 private:
  BoneFem() = default;
  BoneFemConfig config_;
  VertebraLevel level_ = VertebraLevel::kC4;
  VertebraBodyFrame body_;
  TetMesh mesh_;
  BoneRegionLabels labels_;
  std::unique_ptr<BoundarySurface> surface_;
  std::vector<std::uint8_t> fixed_;
  std::unique_ptr<ElasticModel> model_;
};

}  // namespace acdr

// Small-strain linear elasticity on a tetrahedral mesh: linear (4-node) or quadratic (10-node)
// tetrahedra, isotropic material per element, zero-displacement supports per node and axis.
// The stiffness matrix of the free degrees of freedom is assembled and factorised (sparse
// Cholesky) once; each load is then one forward and one back substitution, of which a sparse
// load and a few wanted displacements need only a part (PartialSolve). After
// construction the model is immutable: `solve` and the stress functions are const and keep no
// state, so one model can serve a solver thread (or several) while its owner does other work.
//
// Element formulae: Zienkiewicz, Taylor & Zhu, The Finite Element Method, 7th ed., vol. 1,
// ch. 6 (tetrahedra) and 8 (quadratic shape functions); the 4-point Gauss rule for the
// quadratic tetrahedron integrates its (quadratic) stiffness integrand exactly.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/bone/bone_material.hpp"
#include "engine/bone/tet_mesh.hpp"

namespace acdr {

enum class TetOrder : std::uint8_t { kLinear = 1, kQuadratic = 2 };
const char* tet_order_name(TetOrder order);  ///< "linear" / "quadratic"

/// Stress (Pa) in Voigt order xx, yy, zz, yz, xz, xy.
using Stress6 = Eigen::Matrix<double, 6, 1>;
/// Von Mises equivalent stress (Pa).
double von_mises(const Stress6& s);
/// Principal stresses (Pa), ascending.
Vec3 principal_stresses(const Stress6& s);

/// The nodes of the discretisation: the mesh's corners first, same numbering, then one node per
/// edge for quadratic elements; the element and boundary-face connectivity in those nodes.
struct FeSpace {
  TetOrder order = TetOrder::kLinear;
  std::vector<Vec3> nodes;  ///< corners, then edge midpoints (m)
  std::size_t corner_count = 0;
  int nodes_per_element = 4;  ///< 4 or 10
  /// T * nodes_per_element: corners 0-3, then edges 01, 12, 02, 03, 13, 23.
  std::vector<std::uint32_t> elements;
  /// Per edge node (index minus corner_count): its two corners.
  std::vector<std::array<std::uint32_t, 2>> edge_corners;

  std::span<const std::uint32_t> element(std::size_t t) const {
    return {elements.data() + t * nodes_per_element, static_cast<std::size_t>(nodes_per_element)};
  }
  /// The node on the edge between corners a and b (quadratic only; asserts it exists).
  std::uint32_t edge_node(std::uint32_t a, std::uint32_t b) const;

  /// (lower corner, higher corner, edge node), sorted: the lookup behind edge_node.
  std::vector<std::array<std::uint32_t, 3>> edge_lookup;
};

FeSpace make_fe_space(const TetMesh& mesh, TetOrder order);

/// Supports: bit 0, 1, 2 of `fixed[i]` fix corner node i's x, y, z displacement to zero. An
/// edge node is fixed on an axis when both its corners are.
enum : std::uint8_t { kFixX = 1, kFixY = 2, kFixZ = 4, kFixAll = 7 };

/// Sparse Cholesky factorisations measured for the bone (docs/bone-fem.md): CHOLMOD's
/// simplicial LL' (SuiteSparse; its ordering tries AMD and METIS and keeps the sparser factor),
/// the default, and Eigen's SimplicialLLT (AMD ordering), kept for comparison and tests.
enum class SparseSolverKind : std::uint8_t { kCholmod, kEigenLLT };
const char* sparse_solver_name(SparseSolverKind kind);  ///< "cholmod" / "eigen-llt"

/// Scratch of a solve, kept by the caller between solves (one per solving thread): with it a
/// solve allocates nothing once warm.
struct ElasticSolveWorkspace {
  std::vector<double> y;  ///< in the factor's (permuted) numbering
};

/// Which displacements and stresses a solve must produce when not all of them: what the bone's
/// metrics read is a few hundred elements, and a solve that needs only those skips most of the
/// back substitution (see ElasticModel::partial_solve_for).
struct PartialSolve {
  /// Per column of the factor: its unknown is computed (the wanted ones and every unknown the
  /// back substitution reaches from them, their elimination-tree ancestors).
  std::vector<std::uint8_t> column_needed;
  std::vector<std::uint32_t> elements;  ///< elements whose stress is wanted
  std::size_t needed_columns = 0;
  std::size_t needed_factor_nonzeros = 0;  ///< of the factor, in the needed columns
};

/// What building the model took.
struct ElasticBuildReport {
  std::size_t nodes = 0, elements = 0, free_dofs = 0, fixed_dofs = 0;
  std::size_t stiffness_nonzeros = 0;  ///< lower triangle of the free-dof stiffness
  std::size_t factor_nonzeros = 0;     ///< of the Cholesky factor
  double assemble_seconds = 0.0, factor_seconds = 0.0;
};

class ElasticModel {
 public:
  /// Builds and factorises. `materials` has one entry per tetrahedron, `fixed` one per mesh
  /// node. `stress_materials` (empty: the same) turns each element's strain into the stress
  /// reported for it: for an element that mixes a thin shell and the core, the shell's own
  /// stress. On failure (no support, a singular matrix: a part held by nothing) `ok()` is
  /// false and `error()` says why.
  ElasticModel(const TetMesh& mesh, std::span<const IsotropicMaterial> materials,
               std::span<const std::uint8_t> fixed, TetOrder order,
               SparseSolverKind solver = SparseSolverKind::kCholmod,
               std::span<const IsotropicMaterial> stress_materials = {});
  ~ElasticModel();
  ElasticModel(const ElasticModel&) = delete;
  ElasticModel& operator=(const ElasticModel&) = delete;

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  const FeSpace& space() const { return space_; }
  const ElasticBuildReport& report() const { return report_; }
  std::size_t dof_count() const { return 3 * space_.nodes.size(); }

  /// Displacements (m, 3 per FE node) under nodal forces (N, 3 per FE node; forces on fixed
  /// degrees of freedom are taken by the supports). Both spans have dof_count() entries.
  /// Safe from any thread: each call has its own solver workspace.
  void solve(std::span<const double> force_N, std::span<double> displacement_m) const;
  /// The same with the caller's workspace (no allocation once warm). With `partial`, only the
  /// displacements of the nodes of partial->elements are computed (the others are NaN); they
  /// equal the full solve's bit for bit. The substitutions are our own over CHOLMOD's factor:
  /// the forward one skips the columns a sparse load does not reach (their entry is zero), the
  /// backward one the columns `partial` does not need. Eigen's factor ignores `partial`.
  void solve(std::span<const double> force_N, std::span<double> displacement_m,
             ElasticSolveWorkspace& workspace, const PartialSolve* partial = nullptr) const;
  /// The plan of a solve wanting the stresses of `elements` (see solve).
  PartialSolve partial_solve_for(std::span<const std::uint32_t> elements) const;

  /// Stress at each element's centroid (T entries).
  void element_stress(std::span<const double> displacement_m, std::span<Stress6> out) const;
  /// The same for the listed elements only (the others in `out` are left as they are).
  void element_stress(std::span<const double> displacement_m,
                      std::span<const std::uint32_t> elements, std::span<Stress6> out) const;
  /// Stress at the mesh's corner nodes, averaged over the elements around each, weighted by
  /// volume (corner_count entries): the field for drawing. `element` is element_stress's
  /// result for the same displacement.
  void nodal_stress(std::span<const double> displacement_m, std::span<const Stress6> element,
                    std::span<Stress6> out) const;
  /// Strain energy 0.5 u.K.u (J), from the element matrices.
  double strain_energy(std::span<const double> displacement_m) const;

  /// Element stiffness (dense, 3 * nodes_per_element square) of element t, for tests.
  Eigen::MatrixXd element_stiffness(std::size_t t) const;
  /// Global index of each free dof (dof_count() entries; -1 when fixed).
  const std::vector<int>& free_index() const { return free_index_; }

 private:
  struct Factor;
  Stress6 stress_at(std::size_t t, const std::array<double, 4>& bary,
                    std::span<const double> u) const;

  FeSpace space_;
  std::vector<IsotropicMaterial> materials_;
  std::vector<double> volume_;               // T, m^3
  std::vector<std::array<double, 2>> lame_;  // T: Lame's lambda and mu of the stress, Pa
  std::vector<double> corner_volume_;        // corners: volume of the elements around, m^3
  std::vector<Eigen::Matrix<double, 4, 3>> grad_lambda_;  // T: gradients of the barycentrics
  std::vector<int> free_index_;                           // 3 * FE nodes
  std::vector<std::uint32_t> dof_of_column_;  // CHOLMOD: the dof of each factor column
  std::unique_ptr<Factor> factor_;
  ElasticBuildReport report_;
  std::string error_;
};

}  // namespace acdr

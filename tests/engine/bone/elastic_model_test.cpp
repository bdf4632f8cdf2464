// The elasticity model: element matrices (symmetry, rigid-body modes), the sparse solve
// against a dense solve of the same system, stresses, errors, and solving on another thread.
#include "engine/bone/elastic_model.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <thread>

#include "engine/bone/box_tet_mesh.hpp"

namespace acdr {
namespace {

TetMesh small_block() {
  return make_box_tet_mesh(Vec3::Zero(), Vec3(2e-3, 1e-3, 1e-3), {2, 1, 1});
}

std::vector<std::uint8_t> clamp_x0(const TetMesh& m) {
  std::vector<std::uint8_t> fixed(m.nodes.size(), 0);
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodes[i].x() < 1e-12) fixed[i] = kFixAll;
  return fixed;
}

std::vector<IsotropicMaterial> mixed_materials(const TetMesh& m) {
  std::vector<IsotropicMaterial> out(m.tets.size());
  for (std::size_t t = 0; t < out.size(); ++t) out[t] = {t % 2 ? 100e6 : 12e9, t % 3 ? 0.3 : 0.25};
  return out;
}

class ElasticOrders : public ::testing::TestWithParam<std::tuple<TetOrder, SparseSolverKind>> {};

TEST_P(ElasticOrders, ElementMatrixIsSymmetricAndFreeOfRigidMotion) {
  const auto [order, solver] = GetParam();
  const TetMesh m = small_block();
  const ElasticModel model(m, mixed_materials(m), clamp_x0(m), order, solver);
  ASSERT_TRUE(model.ok()) << model.error();
  const Eigen::MatrixXd k = model.element_stiffness(3);
  EXPECT_LT((k - k.transpose()).norm(), 1e-9 * k.norm());
  // A translation and a small rotation about z strain nothing.
  const int n = model.space().nodes_per_element;
  Eigen::VectorXd translate(3 * n), rotate(3 * n);
  const auto el = model.space().element(3);
  for (int a = 0; a < n; ++a) {
    const Vec3& x = model.space().nodes[el[a]];
    translate.segment<3>(3 * a) = Vec3(1.0, -2.0, 0.5);
    rotate.segment<3>(3 * a) = Vec3(0, 0, 1).cross(x);
  }
  EXPECT_LT((k * translate).norm(), 1e-6 * k.norm());
  EXPECT_LT((k * rotate).norm(), 1e-9 * k.norm());
  // Positive semi-definite: six zero eigenvalues, the rest positive.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(k);
  EXPECT_GT(eig.eigenvalues()[6], 1e-9 * eig.eigenvalues().maxCoeff());
  EXPECT_LT(std::abs(eig.eigenvalues()[5]), 1e-9 * eig.eigenvalues().maxCoeff());
}

TEST_P(ElasticOrders, SparseSolveAgreesWithADenseSolve) {
  const auto [order, solver] = GetParam();
  const TetMesh m = small_block();
  const auto fixed = clamp_x0(m);
  const ElasticModel model(m, mixed_materials(m), fixed, order, solver);
  ASSERT_TRUE(model.ok()) << model.error();
  // Dense global stiffness from the element matrices, reduced to the free dofs.
  const int dofs = static_cast<int>(model.dof_count());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(dofs, dofs);
  const int n = model.space().nodes_per_element;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const Eigen::MatrixXd ke = model.element_stiffness(t);
    const auto el = model.space().element(t);
    for (int r = 0; r < 3 * n; ++r)
      for (int c = 0; c < 3 * n; ++c) k(3 * el[r / 3] + r % 3, 3 * el[c / 3] + c % 3) += ke(r, c);
  }
  std::vector<int> free;
  for (int i = 0; i < dofs; ++i)
    if (model.free_index()[i] >= 0) free.push_back(i);
  Eigen::MatrixXd kf(free.size(), free.size());
  for (std::size_t r = 0; r < free.size(); ++r)
    for (std::size_t c = 0; c < free.size(); ++c) kf(r, c) = k(free[r], free[c]);
  std::vector<double> force(dofs, 0.0), u(dofs);
  for (int i = 0; i < dofs; ++i) force[i] = std::sin(1.0 + i) * 1.0;  // every dof loaded
  Eigen::VectorXd ff(free.size());
  for (std::size_t r = 0; r < free.size(); ++r) ff[r] = force[free[r]];
  const Eigen::VectorXd dense = kf.ldlt().solve(ff);
  model.solve(force, u);
  for (std::size_t r = 0; r < free.size(); ++r)
    EXPECT_NEAR(u[free[r]], dense[r], 1e-9 * dense.cwiseAbs().maxCoeff());
  for (int i = 0; i < dofs; ++i)
    if (model.free_index()[i] < 0) {
      EXPECT_EQ(u[i], 0.0);
    }
  // Energy: 0.5 u.K.u equals half the work of the free forces.
  double work = 0.0;
  for (int i : free) work += force[i] * u[i];
  EXPECT_NEAR(model.strain_energy(u), 0.5 * work, 1e-9 * std::abs(work));
}

TEST_P(ElasticOrders, SolvingOnAnotherThreadGivesTheSameBits) {
  const auto [order, solver] = GetParam();
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3(4e-3, 1e-3, 1e-3), {4, 1, 1});
  const ElasticModel model(m, mixed_materials(m), clamp_x0(m), order, solver);
  ASSERT_TRUE(model.ok());
  std::vector<double> force(model.dof_count(), 0.0);
  force[force.size() - 1] = -1.0;
  std::vector<double> here(model.dof_count()), there(model.dof_count()), again(model.dof_count());
  model.solve(force, here);
  std::thread worker([&] { model.solve(force, there); });
  model.solve(force, again);  // at the same time as the worker
  worker.join();
  EXPECT_EQ(here, there);
  EXPECT_EQ(here, again);
}

INSTANTIATE_TEST_SUITE_P(
    Bone, ElasticOrders,
    ::testing::Combine(::testing::Values(TetOrder::kLinear, TetOrder::kQuadratic),
                       ::testing::Values(SparseSolverKind::kCholmod, SparseSolverKind::kEigenLLT)));

TEST(ElasticModel, QuadraticSpaceHasOneNodePerEdge) {
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3::Ones(), {1, 1, 1});
  const FeSpace s = make_fe_space(m, TetOrder::kQuadratic);
  // A Kuhn cube: 12 cube edges, 6 face diagonals, 1 main diagonal.
  EXPECT_EQ(s.nodes.size(), 8u + 19u);
  for (std::size_t e = 0; e < s.edge_corners.size(); ++e) {
    const auto [a, b] = s.edge_corners[e];
    EXPECT_EQ(s.edge_node(a, b), s.corner_count + e);
    EXPECT_EQ(s.edge_node(b, a), s.corner_count + e);
    EXPECT_EQ(s.nodes[s.corner_count + e], 0.5 * (s.nodes[a] + s.nodes[b]));
  }
}

TEST(ElasticModel, MissingOrUnreachedSupportIsAnError) {
  const TetMesh m = small_block();
  const std::vector<IsotropicMaterial> mat(m.tets.size(), IsotropicMaterial{1e9, 0.3});
  const ElasticModel floating(m, mat, std::vector<std::uint8_t>(m.nodes.size(), 0),
                              TetOrder::kLinear);
  EXPECT_FALSE(floating.ok());
  EXPECT_NE(floating.error().find("no support"), std::string::npos);
  // Two blocks side by side without shared nodes, only one of them held.
  TetMesh two = small_block();
  const TetMesh other = make_box_tet_mesh(Vec3(5e-3, 0, 0), Vec3(6e-3, 1e-3, 1e-3), {1, 1, 1});
  const auto offset = static_cast<std::uint32_t>(two.nodes.size());
  two.nodes.insert(two.nodes.end(), other.nodes.begin(), other.nodes.end());
  for (auto t : other.tets) {
    for (auto& i : t) i += offset;
    two.tets.push_back(t);
  }
  const std::vector<IsotropicMaterial> mat2(two.tets.size(), IsotropicMaterial{1e9, 0.3});
  const ElasticModel half_held(two, mat2, clamp_x0(two), TetOrder::kLinear);
  EXPECT_FALSE(half_held.ok());
  EXPECT_NE(half_held.error().find("connected to no support"), std::string::npos)
      << half_held.error();
}

TEST(ElasticModel, VonMisesAndPrincipalStresses) {
  Stress6 uniaxial;
  uniaxial << -5e6, 0, 0, 0, 0, 0;
  EXPECT_DOUBLE_EQ(von_mises(uniaxial), 5e6);
  Stress6 shear;
  shear << 0, 0, 0, 0, 0, 2e6;  // pure shear xy: principal +-2 MPa, von Mises sqrt(3) 2 MPa
  EXPECT_NEAR(von_mises(shear), std::sqrt(3.0) * 2e6, 1e-6);
  const Vec3 p = principal_stresses(shear);
  EXPECT_NEAR(p[0], -2e6, 1e-6);
  EXPECT_NEAR(p[1], 0.0, 1e-6);
  EXPECT_NEAR(p[2], 2e6, 1e-6);
}

TEST(ElasticModel, NodalStressOfAUniformFieldIsThatField) {
  // Pull a bar with rollers: every element and every node carries the same stress.
  const TetMesh m = make_box_tet_mesh(Vec3::Zero(), Vec3(2, 1, 1), {2, 2, 2});
  std::vector<std::uint8_t> fixed(m.nodes.size(), 0);
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    if (m.nodes[i].x() < 1e-12) fixed[i] |= kFixX;
    if (m.nodes[i].y() < 1e-12) fixed[i] |= kFixY;
    if (m.nodes[i].z() < 1e-12) fixed[i] |= kFixZ;
  }
  const std::vector<IsotropicMaterial> mat(m.tets.size(), IsotropicMaterial{1e9, 0.3});
  const ElasticModel model(m, mat, fixed, TetOrder::kQuadratic);
  ASSERT_TRUE(model.ok());
  // Prescribe the exact field instead of solving: u = (e x, -nu e y, -nu e z).
  std::vector<double> u(model.dof_count());
  const double e = 1e-3;
  for (std::size_t i = 0; i < model.space().nodes.size(); ++i) {
    const Vec3& x = model.space().nodes[i];
    u[3 * i] = e * x.x();
    u[3 * i + 1] = -0.3 * e * x.y();
    u[3 * i + 2] = -0.3 * e * x.z();
  }
  std::vector<Stress6> element(m.tets.size()), nodal(m.nodes.size());
  model.element_stress(u, element);
  model.nodal_stress(u, element, nodal);
  for (const auto& s : nodal) {
    EXPECT_NEAR(s[0], 1e9 * e, 1e-3);
    EXPECT_NEAR(s.tail<5>().norm(), 0.0, 1e-3);
  }
}

}  // namespace
}  // namespace acdr

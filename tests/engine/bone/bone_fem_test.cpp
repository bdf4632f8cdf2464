// A vertebra's elastic model end to end: built from the generated C5, supports on its far
// side, a contact on the near endplate pushes it in, the supports take the load, the model
// serves another thread, and a surface that cannot be meshed is a returned error.
#include "engine/bone/bone_fem.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <thread>

#include "engine/geometry/mesh_io.hpp"
#include "engine/geometry/mesh_shapes.hpp"

namespace acdr {
namespace {

class C5Model : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    BoneFemConfig config;
    config.meshing.size_m = 2.5e-3;
    std::string error;
    report_ = new BoneFemReport();
    bone_ = BoneFem::build(generate_vertebra(SegmentParams{}, VertebraLevel::kC5), SegmentParams{},
                           VertebraLevel::kC5, config, "", report_, &error)
                .release();
    ASSERT_NE(bone_, nullptr) << error;
  }
  static void TearDownTestSuite() {
    delete bone_;
    delete report_;
  }
  static ContactLoad endplate_push(double newtons) {
    ContactLoad c;
    c.point_m = Vec3(0.0, segment_landmarks(SegmentParams{}).c5_upper_endplate_y_m, 1e-3);
    c.force_N = Vec3(0.0, -newtons, 0.0);
    c.radius_m = 1.5e-3;
    return c;
  }
  static BoneFem* bone_;
  static BoneFemReport* report_;
};
BoneFem* C5Model::bone_ = nullptr;
BoneFemReport* C5Model::report_ = nullptr;

TEST_F(C5Model, BuildReportsRegionsSupportsAndFactor) {
  for (int r = 0; r < kBoneRegionCount; ++r) EXPECT_GT(report_->region_tets[r], 0u) << r;
  EXPECT_GT(report_->supported_nodes, 20u);
  EXPECT_GT(report_->elastic.factor_nonzeros, report_->elastic.stiffness_nonzeros);
  // Supports lie on the far (lower) side only.
  const double bottom = bone_->body().center_m.y() - bone_->body().half_height_m;
  for (std::size_t i = 0; i < bone_->mesh().nodes.size(); ++i)
    if (bone_->supports()[i]) {
      EXPECT_LE(bone_->mesh().nodes[i].y(), bottom + bone_->config().support_depth_m + 1e-12);
    }
}

TEST_F(C5Model, EndplatePushMovesTheEndplateDownAndIsLinear) {
  BoneSolution a, b;
  const ContactLoad push = endplate_push(20.0);
  bone_->solve({&push, 1}, a);
  EXPECT_EQ(a.contacts_applied, 1);
  EXPECT_EQ(a.contacts_missed, 0);
  EXPECT_LT((a.applied_force_N - push.force_N).norm(), 1e-12);
  // The node nearest the contact moves down, a few micrometres for 20 N into 100 MPa bone.
  std::size_t nearest = 0;
  for (std::size_t i = 0; i < bone_->mesh().nodes.size(); ++i)
    if ((bone_->mesh().nodes[i] - push.point_m).norm() <
        (bone_->mesh().nodes[nearest] - push.point_m).norm())
      nearest = i;
  const double down = -a.displacement_m[nearest].y();
  EXPECT_GT(down, 0.1e-6);
  EXPECT_LT(down, 100e-6);
  // Supports do not move.
  for (std::size_t i = 0; i < bone_->mesh().nodes.size(); ++i)
    if (bone_->supports()[i]) {
      EXPECT_EQ(a.displacement_m[i].norm(), 0.0);
    }
  // Twice the force, twice everything (linear elasticity).
  const ContactLoad twice = endplate_push(40.0);
  bone_->solve({&twice, 1}, b);
  for (std::size_t t = 0; t < a.element_von_mises_Pa.size(); t += 97)
    EXPECT_NEAR(b.element_von_mises_Pa[t], 2.0 * a.element_von_mises_Pa[t],
                1e-9 * b.element_von_mises_Pa[t] + 1e-9);
  // The highest stress is on the loaded side, near the contact, not at the far supports.
  std::size_t peak = 0;
  for (std::size_t t = 0; t < a.element_von_mises_Pa.size(); ++t)
    if (a.element_von_mises_Pa[t] > a.element_von_mises_Pa[peak]) peak = t;
  EXPECT_GT(bone_->mesh().centroid(peak).y(), bone_->body().center_m.y());
  EXPECT_LT((bone_->mesh().centroid(peak) - push.point_m).norm(), 10e-3);
  // Nodal averages stay within the range of the element values.
  const double max_element = a.element_von_mises_Pa[peak];
  for (double v : a.node_von_mises_Pa) EXPECT_LE(v, max_element * (1.0 + 1e-12));
}

TEST_F(C5Model, SupportsTakeTheWholeLoad) {
  // K u from the element matrices: equal to the applied forces at the free dofs (the solve's
  // residual), and at the fixed dofs the supports' reactions, which balance the load.
  BoneSolution s;
  const ContactLoad push = endplate_push(10.0);
  bone_->solve({&push, 1}, s);
  const ElasticModel& model = bone_->model();
  std::vector<double> ku(model.dof_count(), 0.0);
  const int n = model.space().nodes_per_element;
  for (std::size_t t = 0; t < bone_->mesh().tets.size(); ++t) {
    const auto el = model.space().element(t);
    Eigen::VectorXd ue(3 * n);
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < 3; ++c) ue[3 * a + c] = s.dof_displacement_m[3 * el[a] + c];
    const Eigen::VectorXd fe = model.element_stiffness(t) * ue;
    for (int a = 0; a < 3 * n; ++a) ku[3 * el[a / 3] + a % 3] += fe[a];
  }
  Vec3 reaction = Vec3::Zero();
  double residual = 0.0;
  for (std::size_t i = 0; i < model.dof_count(); ++i) {
    if (model.free_index()[i] < 0)
      reaction[i % 3] += ku[i];
    else
      residual = std::max(residual, std::abs(ku[i] - s.force_N[i]));
  }
  EXPECT_LT(residual, 1e-8 * push.force_N.norm());
  EXPECT_LT((reaction + push.force_N).norm(), 1e-8 * push.force_N.norm());
}

TEST_F(C5Model, SolvesOnItsOwnThreadLikeOnTheCallers) {
  const ContactLoad push = endplate_push(15.0);
  BoneSolution here, there;
  bone_->solve({&push, 1}, here);
  std::thread worker([&] { bone_->solve({&push, 1}, there); });
  worker.join();
  EXPECT_EQ(here.dof_displacement_m, there.dof_displacement_m);
  EXPECT_EQ(here.node_von_mises_Pa, there.node_von_mises_Pa);
}

TEST_F(C5Model, ContactOffTheBoneIsCountedNotApplied) {
  ContactLoad far = endplate_push(5.0);
  far.point_m.y() += 10e-3;  // in the disc space, far above the endplate
  BoneSolution s;
  bone_->solve({&far, 1}, s);
  EXPECT_EQ(s.contacts_applied, 0);
  EXPECT_EQ(s.contacts_missed, 1);
  for (const Vec3& u : s.displacement_m) EXPECT_EQ(u.norm(), 0.0);
}

TEST(BoneFem, ImportedMeshGoesTheSameWay) {
  // C4 written to binary STL in millimetres and read back (single precision, welded), as a
  // segmentation export would come in.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("acdr_bone_c4_" + std::to_string(::getpid()) + ".stl"))
                               .string();
  std::string error;
  ASSERT_TRUE(save_mesh_file(generate_vertebra(SegmentParams{}, VertebraLevel::kC4), path,
                             MeshFormat::kStlBinary, LengthUnit::kMillimetre, &error))
      << error;
  const auto surface = load_closed_mesh_file(path, LengthUnit::kMillimetre, &error);
  std::filesystem::remove(path);
  ASSERT_TRUE(surface) << error;
  BoneFemConfig config;
  config.meshing.size_m = 2.5e-3;
  BoneFemReport report;
  const auto bone =
      BoneFem::build(*surface, SegmentParams{}, VertebraLevel::kC4, config, "", &report, &error);
  ASSERT_NE(bone, nullptr) << error;
  for (int r = 0; r < kBoneRegionCount; ++r) EXPECT_GT(report.region_tets[r], 0u) << r;
  // C4's supports are on its upper side.
  const double top = bone->body().center_m.y() + bone->body().half_height_m;
  for (std::size_t i = 0; i < bone->mesh().nodes.size(); ++i)
    if (bone->supports()[i]) {
      EXPECT_GE(bone->mesh().nodes[i].y(), top - config.support_depth_m - 1e-12);
    }
}

TEST(BoneFem, OpenSurfaceIsAReturnedError) {
  TriangleMesh open = generate_vertebra(SegmentParams{}, VertebraLevel::kC4);
  open.triangles.resize(open.triangles.size() - 10);
  std::string error;
  EXPECT_EQ(BoneFem::build(open, SegmentParams{}, VertebraLevel::kC4, BoneFemConfig{}, "", nullptr,
                           &error),
            nullptr);
  EXPECT_NE(error.find("C4: not a closed surface"), std::string::npos) << error;
}

TEST(BoneFem, SurfaceAwayFromTheBodyHasNoSupport) {
  // A closed box far below C4's upper endplate: meshable, but nothing on the far side.
  const TriangleMesh box = make_box_mesh(Vec3(-5e-3, -30e-3, -5e-3), Vec3(5e-3, -25e-3, 5e-3));
  std::string error;
  BoneFemConfig config;
  config.meshing.size_m = 2.5e-3;
  EXPECT_EQ(BoneFem::build(box, SegmentParams{}, VertebraLevel::kC4, config, "", nullptr, &error),
            nullptr);
  EXPECT_NE(error.find("no surface node lies on the far endplate"), std::string::npos) << error;
}

TEST(BoneFem, BadConfigurationIsNamed) {
  BoneFemConfig config;
  config.support_depth_m = 0.0;
  config.materials.cancellous.youngs_modulus_Pa = 0.0;
  EXPECT_NE(validate_bone_fem_config(config).find("support_depth_m"), std::string::npos);
  EXPECT_NE(validate_bone_fem_config(config).find("cancellous.youngs_modulus_Pa"),
            std::string::npos);
  std::string error;
  EXPECT_EQ(BoneFem::build(generate_vertebra(SegmentParams{}, VertebraLevel::kC5), SegmentParams{},
                           VertebraLevel::kC5, config, "", nullptr, &error),
            nullptr);
  EXPECT_NE(error.find("bad bone model configuration"), std::string::npos) << error;
}

}  // namespace
}  // namespace acdr

// Region labels of a generated C5: every region present and where anatomy puts it, shell
// fractions that add up to the shell's volume, and the exact volume fraction below a level.
#include "engine/bone/bone_regions.hpp"

#include <gtest/gtest.h>

#include "engine/bone/tet_mesher.hpp"

namespace acdr {
namespace {

class C5Regions : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    TetMeshingParams p;
    p.size_m = 2.0e-3;
    auto r = mesh_closed_surface(generate_vertebra(SegmentParams{}, VertebraLevel::kC5), p);
    ASSERT_TRUE(r.mesh) << r.error;
    mesh_ = new TetMesh(std::move(*r.mesh));
  }
  static void TearDownTestSuite() { delete mesh_; }
  static TetMesh* mesh_;
};
TetMesh* C5Regions::mesh_ = nullptr;

TEST_F(C5Regions, EveryRegionIsPresentWhereAnatomyPutsIt) {
  const TetMesh& m = *mesh_;
  const BoundarySurface surface(m);
  const VertebraBodyFrame body = vertebra_body_frame(SegmentParams{}, VertebraLevel::kC5);
  const BoneShellParams shell;
  const BoneRegionLabels labels = classify_bone_regions(m, surface, body, shell);
  ASSERT_EQ(labels.region.size(), m.tets.size());
  std::array<double, kBoneRegionCount> volume{};
  double shell_volume = 0.0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto region = static_cast<BoneRegion>(labels.region[t]);
    const double v = std::abs(m.tet_volume(t));
    volume[labels.region[t]] += v;
    const Vec3 q = m.centroid(t) - body.center_m;
    switch (region) {
      case BoneRegion::kPosterior:
        EXPECT_TRUE(q.z() < body.back_z_m || std::abs(q.x()) > body.half_width_m);
        EXPECT_EQ(labels.shell_fraction[t], 0.0);
        break;
      case BoneRegion::kEndplate:
        // Near the top or bottom of the body.
        EXPECT_GT(std::abs(q.y()), body.half_height_m - 3e-3) << "tet " << t;
        [[fallthrough]];
      case BoneRegion::kCortical:
        EXPECT_GT(labels.shell_fraction[t], 0.0);
        EXPECT_LE(labels.shell_fraction[t], 1.0);
        shell_volume += labels.shell_fraction[t] * v;
        break;
      case BoneRegion::kCancellous:
        EXPECT_EQ(labels.shell_fraction[t], 0.0);
        EXPECT_GE(std::abs(q.z() - 0.0), 0.0);
        break;
    }
  }
  for (int r = 0; r < kBoneRegionCount; ++r)
    EXPECT_GT(volume[r], 0.0) << bone_region_name(static_cast<BoneRegion>(r));
  // The posterior elements are a large share of a cervical vertebra; the body the rest.
  const double total = m.volume();
  EXPECT_GT(volume[3] / total, 0.3);
  EXPECT_LT(volume[3] / total, 0.8);
  // The shell's volume is its thickness times the body's surface, within the sampling and the
  // thickness mix (0.4 and 0.5 mm): between 0.3 mm and 0.6 mm times the body surface area.
  double body_area = 0.0;
  for (std::size_t f = 0; f < surface.faces().size(); ++f) {
    const auto& n = surface.faces()[f].nodes;
    const Vec3 q = (m.nodes[n[0]] + m.nodes[n[1]] + m.nodes[n[2]]) / 3.0 - body.center_m;
    if (q.z() >= body.back_z_m && std::abs(q.x()) <= body.half_width_m)
      body_area += surface.face_area(f);
  }
  EXPECT_GT(shell_volume, 0.3e-3 * body_area);
  EXPECT_LT(shell_volume, 0.6e-3 * body_area);
  // Depths: zero on the surface, positive inside, capped.
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    if (surface.on_surface()[i]) {
      EXPECT_EQ(labels.node_depth_m[i], 0.0);
    } else {
      EXPECT_GT(labels.node_depth_m[i], 0.0);
    }
    EXPECT_LE(labels.node_depth_m[i], labels.depth_cap_m);
  }
}

TEST_F(C5Regions, ThickerShellTakesMoreVolume) {
  const BoundarySurface surface(*mesh_);
  const VertebraBodyFrame body = vertebra_body_frame(SegmentParams{}, VertebraLevel::kC5);
  BoneShellParams thin, thick;
  thick.cortical_thickness_m = 0.8e-3;
  auto shell_volume = [&](const BoneShellParams& s) {
    const BoneRegionLabels l = classify_bone_regions(*mesh_, surface, body, s);
    double v = 0.0;
    for (std::size_t t = 0; t < mesh_->tets.size(); ++t)
      if (l.region[t] == static_cast<std::uint8_t>(BoneRegion::kCortical))
        v += l.shell_fraction[t] * std::abs(mesh_->tet_volume(t));
    return v;
  };
  EXPECT_GT(shell_volume(thick), 1.6 * shell_volume(thin));
}

TEST(BoneRegions, FractionBelowALinearField) {
  EXPECT_EQ(fraction_below({0, 0, 0, 0}, 1.0), 1.0);
  EXPECT_EQ(fraction_below({2, 3, 4, 5}, 1.0), 0.0);
  // One corner at 0, the others at 1: the part below t is a corner tet of volume t^3.
  for (double t : {0.25, 0.5, 0.75})
    EXPECT_NEAR(fraction_below({0, 1, 1, 1}, t), t * t * t, 0.02) << t;
  // Symmetric field: half below the mean.
  EXPECT_NEAR(fraction_below({0, 0, 1, 1}, 0.5), 0.5, 0.01);
}

}  // namespace
}  // namespace acdr

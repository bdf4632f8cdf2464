// The dashboard's bone stress pane, its data side: built from a scenario with the bone model and
// a recording's load samples, it shows each vertebra's disc-side surface (facing the disc),
// solves the sample at the chosen time (and only when the time moves to another sample), finds
// the attempt's peak bone load, and is absent, with the reason, where there is nothing to show.
#include "ui/bone_stress_pane.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include "engine/anatomy/vertebra_generator.hpp"
#include "tests/engine/anatomy/coarse_segment_scene.hpp"

namespace acdr {
namespace {

class StressPane : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (std::filesystem::temp_directory_path() /
            ("acdr_bone_pane_" + std::to_string(::getpid())))
               .string();
    std::filesystem::remove_all(dir_);
    scenario_.path = dir_ + "/segment.json";
    scenario_.hash = "test";
    scenario_.id = "bone-pane";
    scenario_.world = test::coarse_segment_world(dir_);
    scenario_.bone.enabled = true;
    scenario_.bone.fem.meshing.size_m = 3.0e-3;  // coarse: a few seconds to mesh
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  /// A push of `newtons` into the middle of C5's upper endplate.
  BoneLoadPoint c5_push(float newtons) const {
    const SegmentLandmarks l = segment_landmarks(scenario_.world.anatomy.segment);
    BoneLoadPoint p;
    p.point_m = Eigen::Vector3f(0.0f, static_cast<float>(l.c5_upper_endplate_y_m), 1e-3f);
    p.force_N = Eigen::Vector3f(0.0f, -newtons, 0.0f);
    p.radius_m = 1.5e-3f;
    p.vertebra = 1;
    return p;
  }
  std::string dir_;
  ScenarioModel scenario_;
};

TEST_F(StressPane, ShowsTheDiscSideUnderTheSampleAtTheChosenTime) {
  AttemptRecording rec;
  rec.bone_loads = {{0.01, {c5_push(5.0f)}}, {0.02, {c5_push(10.0f)}}, {0.03, {}}};
  std::string why;
  auto pane = BoneStressPane::create(scenario_, rec, &why);
  ASSERT_NE(pane, nullptr) << why;
  EXPECT_DOUBLE_EQ(pane->peak_load_t_s(), 0.02);
  EXPECT_DOUBLE_EQ(pane->peak_load_N(), 10.0);
  for (int v = 0; v < 2; ++v) {
    const EndplateSurface& s = pane->surface(v);
    ASSERT_FALSE(s.triangles.empty()) << v;
    // Every triangle faces the disc: down for C4, up for C5 (counter-clockwise from outside).
    for (const auto& t : s.triangles) {
      const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
      EXPECT_GT((v == 0 ? -1.0 : 1.0) * n.y(), 0.19);
    }
  }
  pane->show_time(0.015);  // the sample at 0.01 s
  EXPECT_DOUBLE_EQ(pane->sample_t_s(), 0.01);
  EXPECT_TRUE(pane->sample_solved());
  const std::vector<double> five = pane->surface(1).stress_Pa;
  EXPECT_GT(*std::max_element(five.begin(), five.end()), 0.0);
  EXPECT_GT(pane->surface(1).endplate_peak_Pa, 0.0);
  for (double s : pane->surface(0).stress_Pa) EXPECT_EQ(s, 0.0);  // C4 not loaded
  pane->show_time(0.02);  // twice the push: twice the stress (linear elasticity)
  for (std::size_t k = 0; k < five.size(); ++k)
    EXPECT_NEAR(pane->surface(1).stress_Pa[k], 2.0 * five[k], 1e-9 * five[k] + 1e-6) << k;
  pane->show_time(0.5);  // after the last sample: the last one, with no load
  EXPECT_DOUBLE_EQ(pane->sample_t_s(), 0.03);
  EXPECT_FALSE(pane->sample_solved());
  pane->show_time(0.0);  // before the first: the first
  EXPECT_DOUBLE_EQ(pane->sample_t_s(), 0.01);
  // The scale: the attempt's endplate peak, rounded up.
  pane->set_scale_top(3.3e6);
  EXPECT_DOUBLE_EQ(pane->scale_top_Pa(), 5e6);
}

TEST_F(StressPane, AbsentWithTheReasonWhenThereIsNothingToShow) {
  AttemptRecording rec;
  std::string why;
  EXPECT_EQ(BoneStressPane::create(scenario_, rec, &why), nullptr);
  EXPECT_NE(why.find("no bone load samples"), std::string::npos) << why;
  rec.bone_loads = {{0.01, {c5_push(5.0f)}}};
  ScenarioModel plain = scenario_;
  plain.bone.enabled = false;
  EXPECT_EQ(BoneStressPane::create(plain, rec, &why), nullptr);
  EXPECT_NE(why.find("does not model the bone"), std::string::npos) << why;
}

TEST(NiceStressTop, RoundsUpToOneTwoTwoAndAHalfOrFive) {
  EXPECT_DOUBLE_EQ(nice_stress_top(0.077e6), 0.1e6);
  EXPECT_DOUBLE_EQ(nice_stress_top(0.125e6), 0.2e6);
  EXPECT_DOUBLE_EQ(nice_stress_top(7.56e6), 10e6);
  EXPECT_DOUBLE_EQ(nice_stress_top(2.2e6), 2.5e6);
  EXPECT_DOUBLE_EQ(nice_stress_top(0.0), 1e6);
}

}  // namespace
}  // namespace acdr

// The segment's two vertebrae under sampled loads: the measured places lie where they should
// (the endplates on the disc side, the posterior elements near the pedicles), a push on C5's
// endplate stresses C5 only and linearly, an unloaded vertebra is not solved, and the history
// of samples sums peaks and time above warning the same way however it is fed.
#include "engine/bone/bone_segment.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/bone/bone_stress_history.hpp"
#include "tests/engine/anatomy/coarse_segment_scene.hpp"

namespace acdr {
namespace {

class Segment : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    anatomy_ = new Anatomy(test::coarse_anatomy("none"));
    BoneModelConfig config;
    config.enabled = true;
    config.fem.meshing.size_m = 3.0e-3;  // coarse: meshing both takes a few seconds, uncached
    std::string error;
    bone_ = BoneSegment::build(*anatomy_, config, "", &error).release();
    ASSERT_NE(bone_, nullptr) << error;
  }
  static void TearDownTestSuite() {
    delete bone_;
    delete anatomy_;
  }
  /// A push of `newtons` into the middle of C5's upper endplate.
  static BoneLoadPoint c5_push(float newtons) {
    BoneLoadPoint p;
    p.point_m = Eigen::Vector3f(0.0f, static_cast<float>(anatomy_->landmarks().c5_upper_endplate_y_m),
                                1e-3f);
    p.force_N = Eigen::Vector3f(0.0f, -newtons, 0.0f);
    p.radius_m = 1.5e-3f;
    p.vertebra = 1;
    return p;
  }
  static Anatomy* anatomy_;
  static BoneSegment* bone_;
};
Anatomy* Segment::anatomy_ = nullptr;
BoneSegment* Segment::bone_ = nullptr;

TEST_F(Segment, MeasuredPlacesLieOnTheDiscSideAndNearThePedicles) {
  for (int m = 0; m < kBoneMeasureCount; ++m) {
    const auto measure = static_cast<BoneMeasure>(m);
    const BoneFem& fem = bone_->vertebra(bone_measure_vertebra(measure));
    const auto& elements = bone_->measure_elements(measure);
    ASSERT_FALSE(elements.empty()) << bone_measure_name(measure);
    for (std::uint32_t t : elements) {
      Vec3 c = Vec3::Zero();
      for (std::uint32_t n : fem.mesh().tets[t]) c += fem.mesh().nodes[n] / 4.0;
      const Vec3 rel = c - fem.body().center_m;
      const auto region = static_cast<BoneRegion>(fem.labels().region[t]);
      if (bone_measure_is_endplate(measure)) {
        EXPECT_EQ(region, BoneRegion::kEndplate);
        // C4's inferior endplate lies below its centre, C5's superior one above.
        EXPECT_GT(measure == BoneMeasure::kC4InferiorEndplate ? -rel.y() : rel.y(), 0.0);
      } else {
        EXPECT_EQ(region, BoneRegion::kPosterior);
        EXPECT_GE(rel.z(), fem.body().back_z_m - 6.0e-3 - 1e-12);
      }
    }
  }
}

TEST_F(Segment, PushOnC5StressesC5OnlyAndLinearly) {
  BoneSegmentScratch scratch;
  const BoneLoadPoint once[] = {c5_push(10.0f)};
  const BoneLoadPoint twice[] = {c5_push(20.0f)};
  const BoneSampleResult a = bone_->solve(0.01, once, scratch);
  const BoneSampleResult b = bone_->solve(0.02, twice, scratch);
  EXPECT_FALSE(a.solved[0]);
  EXPECT_TRUE(a.solved[1]);
  EXPECT_DOUBLE_EQ(a.load_N, 10.0);
  EXPECT_EQ(a.peak_Pa[static_cast<int>(BoneMeasure::kC4InferiorEndplate)], 0.0);
  EXPECT_EQ(a.peak_Pa[static_cast<int>(BoneMeasure::kC4Posterior)], 0.0);
  const double endplate = a.peak_Pa[static_cast<int>(BoneMeasure::kC5SuperiorEndplate)];
  // 10 N over a 1.5 mm patch: a few MPa in the bony endplate (docs/bone-fem.md).
  EXPECT_GT(endplate, 0.3e6);
  EXPECT_LT(endplate, 30e6);
  EXPECT_GT(endplate, a.peak_Pa[static_cast<int>(BoneMeasure::kC5Posterior)]);
  for (int m = 0; m < kBoneMeasureCount; ++m)
    EXPECT_NEAR(b.peak_Pa[m], 2.0 * a.peak_Pa[m], 1e-9 * b.peak_Pa[m] + 1e-9) << m;
  // Below the smallest load worth a solve, nothing is solved.
  const BoneLoadPoint tiny[] = {c5_push(1e-3f)};
  const BoneSampleResult c = bone_->solve(0.03, tiny, scratch);
  EXPECT_FALSE(c.solved[0] || c.solved[1]);
  for (double p : c.peak_Pa) EXPECT_EQ(p, 0.0);
}

TEST_F(Segment, MeasuredSolveEqualsTheFullSolveBitForBitAndSkipsPartOfTheFactor) {
  // Pushes on both vertebrae; the metrics' solve (partial: the measured elements only) against
  // the drawing's (everything, with nodal stresses).
  BoneLoadPoint c4 = c5_push(8.0f);
  c4.vertebra = 0;
  c4.point_m.y() = static_cast<float>(anatomy_->landmarks().c4_lower_endplate_y_m);
  c4.force_N = Eigen::Vector3f(0.0f, 8.0f, 0.0f);
  const BoneLoadPoint loads[] = {c5_push(12.0f), c4};
  BoneSegmentScratch partial, full;
  full.nodal_fields = true;
  const BoneSampleResult a = bone_->solve(0.01, loads, partial);
  const BoneSampleResult b = bone_->solve(0.01, loads, full);
  ASSERT_TRUE(a.solved[0] && a.solved[1]);
  EXPECT_EQ(a.peak_Pa, b.peak_Pa);
  for (int v = 0; v < 2; ++v) {
    const PartialSolve& plan = bone_->measured_solve(v);
    EXPECT_GT(plan.needed_columns, 0u);
    EXPECT_LT(plan.needed_factor_nonzeros,
              bone_->vertebra(v).model().report().factor_nonzeros);
    for (std::uint32_t t : plan.elements) {
      EXPECT_EQ(partial.solution[v].element_von_mises_Pa[t], full.solution[v].element_von_mises_Pa[t]);
      for (std::uint32_t n : bone_->vertebra(v).mesh().tets[t])
        EXPECT_EQ(partial.solution[v].displacement_m[n], full.solution[v].displacement_m[n]);
    }
    // What the partial solve did not compute says so.
    std::size_t not_computed = 0;
    for (double s : partial.solution[v].element_von_mises_Pa) not_computed += std::isnan(s);
    EXPECT_EQ(not_computed, partial.solution[v].element_von_mises_Pa.size() - plan.elements.size());
    EXPECT_TRUE(partial.solution[v].node_von_mises_Pa.empty());
    EXPECT_EQ(full.solution[v].node_von_mises_Pa.size(), bone_->vertebra(v).mesh().nodes.size());
  }
}

TEST_F(Segment, HistorySumsPeaksAndTimeAboveWarningTheSameWayEachTime) {
  std::vector<BoneLoadRecord> samples;
  for (int k = 0; k < 12; ++k) {
    BoneLoadRecord& r = samples.emplace_back();
    r.t_s = 0.01 * (k + 1);
    if (k % 3 != 0) r.points.push_back(c5_push(static_cast<float>(2 * k)));
  }
  const BoneStressSummary once = analyse_bone_loads(*bone_, samples);
  // Fed one by one through a history of its own: the same figures bit for bit.
  BoneStressHistory history(bone_->config().strengths, bone_->config().sample_period_s);
  BoneSegmentScratch scratch;
  std::vector<BoneSampleResult> results;
  for (const BoneLoadRecord& r : samples) {
    results.push_back(bone_->solve(r.t_s, r.points, scratch));
    history.add(results.back());
  }
  const BoneStressSummary& again = history.summary();
  EXPECT_EQ(once.peak_Pa, again.peak_Pa);
  EXPECT_EQ(once.endplate_over_warning_s, again.endplate_over_warning_s);
  EXPECT_EQ(once.samples, 12);
  EXPECT_EQ(once.solves, 8);
  // The largest push is the last loaded sample (k = 11, 22 N).
  EXPECT_DOUBLE_EQ(once.peak_load_N, 22.0);
  EXPECT_DOUBLE_EQ(once.peak_load_t_s, 0.12);
  EXPECT_DOUBLE_EQ(once.peak_stress_t_s, 0.12);
  // Time above warning: one period per sample whose endplate peak passes the warning. With
  // the warning at the 10 N push's peak, the 14, 16, 20 and 22 N pushes pass it.
  BoneStrengths strengths;
  strengths.warning_fraction = 0.5;
  strengths.endplate_Pa = 2.0 * std::max(results[5].peak_Pa[0], results[5].peak_Pa[1]);  // 10 N
  BoneStressHistory warned(strengths, 0.01);
  for (const BoneSampleResult& r : results) warned.add(r);
  EXPECT_NEAR(warned.summary().endplate_over_warning_s, 0.04, 1e-12);
}

}  // namespace
}  // namespace acdr

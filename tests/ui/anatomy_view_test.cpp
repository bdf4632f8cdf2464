// Anterior and lateral pictures of the segment: the cameras look from the front and from the
// patient's left, and every label's point lands inside the picture.
#include "ui/anatomy_view.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "tests/engine/anatomy/coarse_segment_scene.hpp"
#include "ui/render_camera.hpp"

namespace acdr {
namespace {

TEST(AnatomyView, ParsesTheThreeViews) {
  AnatomyView v = AnatomyView::kSurgeon;
  EXPECT_TRUE(parse_anatomy_view("anterior", &v));
  EXPECT_EQ(v, AnatomyView::kAnterior);
  EXPECT_TRUE(parse_anatomy_view("lateral", &v));
  EXPECT_EQ(v, AnatomyView::kLateral);
  EXPECT_TRUE(parse_anatomy_view("surgeon", &v));
  EXPECT_EQ(v, AnatomyView::kSurgeon);
  EXPECT_FALSE(parse_anatomy_view("top", &v));
}

TEST(AnatomyView, CamerasLookFromTheFrontAndTheLeftAndFrameEveryLabel) {
  const std::string cache = (std::filesystem::temp_directory_path() / "acdr_anatomy_view_test").string();
  const World world(test::coarse_segment_world(cache));
  ASSERT_NE(world.anatomy(), nullptr);
  const int width = 1280, height = 800;
  EXPECT_TRUE(anatomy_labels(world, AnatomyView::kSurgeon).empty());
  for (AnatomyView view : {AnatomyView::kAnterior, AnatomyView::kLateral}) {
    const RenderCamera camera = anatomy_camera(*world.anatomy(), view, static_cast<float>(width) / height);
    const Eigen::Vector3f look = camera.eye - camera.target;
    if (view == AnatomyView::kAnterior) {
      EXPECT_GT(look.z(), 0.0f);  // from the front (+z)
      EXPECT_NEAR(look.x(), 0.0f, 1e-6f);
    } else {
      EXPECT_GT(look.x(), 0.0f);  // from the patient's left (+x)
      EXPECT_NEAR(look.z(), 0.0f, 1e-6f);
    }
    EXPECT_FLOAT_EQ(camera.up.y(), 1.0f);  // cranial up
    const auto labels = anatomy_labels(world, view);
    EXPECT_GE(labels.size(), 10u);
    int left = 0, right = 0;
    for (const AnatomyLabel& label : labels) {
      const auto px = project_to_pixel(camera, width, height, label.point_m);
      ASSERT_TRUE(px.has_value()) << label.text;
      EXPECT_GT(px->x(), 0.0f) << label.text;
      EXPECT_LT(px->x(), width) << label.text;
      EXPECT_GT(px->y(), 0.0f) << label.text;
      EXPECT_LT(px->y(), height) << label.text;
      (label.column < 0 ? left : right) += 1;
    }
    EXPECT_GT(left, 0);
    EXPECT_GT(right, 0);
  }
}

// The posterior longitudinal ligament is named in the lateral picture when the scene has it.
TEST(AnatomyView, TheLateralPictureNamesTheLigamentWhenTheSceneHasIt) {
  const std::string cache = (std::filesystem::temp_directory_path() / "acdr_anatomy_view_test").string();
  auto named = [](const std::vector<AnatomyLabel>& labels) {
    return std::count_if(labels.begin(), labels.end(), [](const AnatomyLabel& l) {
      return l.text == "posterior longitudinal ligament";
    });
  };
  WorldConfig config = test::coarse_segment_world(cache);
  EXPECT_EQ(named(anatomy_labels(World(config), AnatomyView::kLateral)), 0);
  config.anatomy.posterior_ligament = true;
  const World world(config);
  const auto labels = anatomy_labels(world, AnatomyView::kLateral);
  ASSERT_EQ(named(labels), 1);
  EXPECT_EQ(named(anatomy_labels(world, AnatomyView::kAnterior)), 0);  // behind the disc
  const RenderCamera camera = anatomy_camera(*world.anatomy(), AnatomyView::kLateral, 1.6f);
  for (const AnatomyLabel& label : labels) {
    if (label.text != "posterior longitudinal ligament") continue;
    // On the ligament's face, between the bodies, and in the picture.
    EXPECT_NEAR(label.point_m.z(), world.anatomy()->landmarks().body_back_z_m - 0.5e-3, 1e-6);
    EXPECT_TRUE(project_to_pixel(camera, 1280, 800, label.point_m).has_value());
  }
}

}  // namespace
}  // namespace acdr

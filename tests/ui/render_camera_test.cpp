// Tests of ui/render_camera: matrices, projection to pixels, and framing of a bounding box.
#include "ui/render_camera.hpp"

#include <gtest/gtest.h>

#include "ui/mesh_primitives.hpp"

namespace acdr {
namespace {

TEST(RenderCamera, ViewMatrixPutsTheEyeAtTheOriginLookingDownMinusZ) {
  RenderCamera cam;
  cam.eye = {0.1f, -0.2f, 0.3f};
  cam.target = {0.0f, 0.05f, 0.0f};
  const Eigen::Matrix4f v = view_matrix(cam);
  EXPECT_TRUE((v * cam.eye.homogeneous()).head<3>().isZero(1e-6f));
  const Eigen::Vector3f t = (v * cam.target.homogeneous()).head<3>();
  EXPECT_NEAR(t.x(), 0.0f, 1e-6f);
  EXPECT_NEAR(t.y(), 0.0f, 1e-6f);
  EXPECT_NEAR(t.z(), -(cam.target - cam.eye).norm(), 1e-6f);
  // World up stays up on screen.
  const Eigen::Vector3f above = (v * (cam.target + Eigen::Vector3f(0, 0, 0.01f)).homogeneous()).head<3>();
  EXPECT_GT(above.y(), 0.0f);
}

TEST(RenderCamera, ProjectsTheTargetToTheImageCentre) {
  RenderCamera cam;
  const auto p = project_to_pixel(cam, 640, 360, cam.target);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x(), 320.0f, 1e-3f);
  EXPECT_NEAR(p->y(), 180.0f, 1e-3f);
  // Up in the world is up in the image (smaller row index).
  const auto q = project_to_pixel(cam, 640, 360, cam.target + Eigen::Vector3f(0, 0, 0.01f));
  ASSERT_TRUE(q);
  EXPECT_LT(q->y(), 180.0f);
}

TEST(RenderCamera, PointsBehindTheCameraDoNotProject) {
  RenderCamera cam;
  const Eigen::Vector3f behind = cam.eye + (cam.eye - cam.target);
  EXPECT_FALSE(project_to_pixel(cam, 100, 100, behind));
}

TEST(RenderCamera, LookingStraightDownStaysFinite) {
  RenderCamera cam;
  cam.eye = {0, 0, 1};
  cam.target = {0, 0, 0};
  EXPECT_TRUE(view_matrix(cam).allFinite());
}

TEST(RenderCamera, FrameBoundsFitsEveryCornerTightly) {
  const Eigen::Vector3f lo(-0.022f, -0.012f, -0.002f), hi(0.022f, 0.012f, 0.06f);
  for (float aspect : {16.0f / 9.0f, 1.0f, 0.6f}) {
    const int w = static_cast<int>(400 * aspect), h = 400;
    const RenderCamera cam = frame_bounds(lo, hi, aspect);
    float min_margin = 1e9f;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3f p((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                              (c & 4) ? hi.z() : lo.z());
      const auto px = project_to_pixel(cam, w, h, p);
      ASSERT_TRUE(px);
      EXPECT_GE(px->x(), 0.0f);
      EXPECT_LE(px->x(), w);
      EXPECT_GE(px->y(), 0.0f);
      EXPECT_LE(px->y(), h);
      min_margin = std::min({min_margin, px->x(), w - px->x(), px->y(), h - px->y()});
      // Inside the depth range too.
      const float depth = -(view_matrix(cam) * p.homogeneous()).z();
      EXPECT_GT(depth, cam.near_m);
      EXPECT_LT(depth, cam.far_m);
    }
    // Tight: some corner comes within the 10 % margin band of an edge.
    EXPECT_LT(min_margin, 0.12f * std::max(w, h)) << "aspect " << aspect;
  }
}

TEST(RenderCamera, SceneBoundsCoverMeshesAndVisibleParticles) {
  RenderScene scene;
  scene.meshes.push_back(make_box({0, 0, 0}, {1, 1, 1}));
  scene.meshes.back().pose = Eigen::Affine3f(Eigen::Translation3f(10, 0, 0));
  scene.particles.positions = {{-5, 0, 0}, {0, 0, 50}};
  scene.particles.colors = {{1, 1, 1, 1}, {1, 1, 1, 0}};  // the second one hidden
  scene.particles.radius_m = 0.5f;
  const auto b = scene_bounds(scene);
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->min.x(), -5.5f, 1e-6f);
  EXPECT_NEAR(b->max.x(), 11.0f, 1e-6f);
  EXPECT_NEAR(b->max.z(), 1.0f, 1e-6f);
  EXPECT_FALSE(scene_bounds(RenderScene()));
}

TEST(RenderCamera, FrameSceneLeavesOutMeshesExcludedFromFraming) {
  RenderScene scene;
  scene.meshes.push_back(make_box({0, 0, 0}, {0.02f, 0.02f, 0.02f}));
  scene.meshes.push_back(make_cylinder({0.01f, 0.01f, 0.03f}, {0.01f, 0.01f, 0.2f}, 0.001f));
  const RenderCamera all = frame_scene(scene, 1.0f);
  scene.meshes[1].include_in_framing = false;
  const RenderCamera site = frame_scene(scene, 1.0f);
  // Framing the box alone brings the camera much closer, centred on the box.
  EXPECT_LT((site.eye - site.target).norm(), 0.5f * (all.eye - all.target).norm());
  EXPECT_TRUE(site.target.isApprox(Eigen::Vector3f(0.01f, 0.01f, 0.01f), 1e-5f));
  // Excluding everything falls back to framing everything.
  scene.meshes[0].include_in_framing = false;
  EXPECT_TRUE(frame_scene(scene, 1.0f).eye.isApprox(all.eye, 1e-5f));
}

}  // namespace
}  // namespace acdr

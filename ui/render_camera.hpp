// The math of a RenderCamera: view and projection matrices, projecting a world point to a
// pixel, and a default camera that frames a scene's bounding box.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "ui/render_scene.hpp"

namespace acdr {

/// World -> view (eye at the origin looking down -z, `up` projected to +y). Right-handed,
/// as OpenGL expects.
Eigen::Matrix4f view_matrix(const RenderCamera& camera);

/// View -> clip space, OpenGL convention (depth -1..1), `aspect` = width / height.
Eigen::Matrix4f projection_matrix(const RenderCamera& camera, float aspect);

/// Where a world point lands in an image of width x height pixels, with (0,0) the top-left
/// pixel corner (image convention, as in a PNG). Empty when the point is behind the camera.
std::optional<Eigen::Vector2f> project_to_pixel(const RenderCamera& camera, int width, int height,
                                                const Eigen::Vector3f& world);

struct Bounds3f {
  Eigen::Vector3f min = Eigen::Vector3f::Zero();
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
};

/// Axis-aligned bounds of what a scene draws: mesh vertices after their pose, particle centres
/// grown by the radius (hidden particles excluded). The ground plane is not included. With
/// `framing_only`, meshes whose include_in_framing is false are left out. Empty when nothing
/// is drawn.
std::optional<Bounds3f> scene_bounds(const RenderScene& scene, bool framing_only = false);

/// The direction the default camera looks from (from the target towards the eye): front-right
/// and above, like the seed's figures of the box.
inline Eigen::Vector3f default_view_direction() { return Eigen::Vector3f(0.55f, -0.75f, 0.62f); }

/// A camera looking at the centre of the box from `view_direction` (target -> eye, any length),
/// placed just far enough that all eight corners fit into the image with a margin
/// (`margin` = 1.1 leaves 10 % around). Near and far planes bracket the box and the ground.
RenderCamera frame_bounds(const Eigen::Vector3f& min, const Eigen::Vector3f& max, float aspect,
                          const Eigen::Vector3f& view_direction = default_view_direction(),
                          float fov_y_deg = 35.0f, float margin = 1.1f);

/// frame_bounds() of the scene's framing bounds (scene_bounds(scene, true), or all of it when
/// that is empty); returns the scene's own camera when nothing is drawn.
RenderCamera frame_scene(const RenderScene& scene, float aspect,
                         const Eigen::Vector3f& view_direction = default_view_direction());

}  // namespace acdr

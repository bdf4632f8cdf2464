// A synthetic scene in the seed's proof-of-concept layout (an open box of five walls, a block of
// nucleus particles, a prism instrument above, a translucent danger zone), built from plain
// numbers with no engine. Shared by the renderer tests, render timing, and previews.
#pragma once

#include <Eigen/Core>

#include "ui/render_scene.hpp"

namespace acdr {

/// Colours of the sample scene, so tests can look for them.
struct SampleSceneColors {
  Eigen::Vector4f walls = Eigen::Vector4f(0.42f, 0.55f, 0.68f, 1.0f);       ///< blue-grey
  Eigen::Vector4f particles = Eigen::Vector4f(0.96f, 0.76f, 0.28f, 1.0f);   ///< nucleus yellow
  Eigen::Vector4f instrument = Eigen::Vector4f(0.78f, 0.80f, 0.83f, 1.0f);  ///< steel
  Eigen::Vector4f zone = Eigen::Vector4f(0.95f, 0.08f, 0.06f, 0.35f);       ///< danger, translucent
};

/// Where the parts of the sample scene are (world frame, m), for tests and framing.
struct SampleSceneLayout {
  Eigen::Vector3f inner_min = Eigen::Vector3f(-0.020f, -0.010f, 0.0f);  ///< box cavity
  Eigen::Vector3f inner_max = Eigen::Vector3f(0.020f, 0.010f, 0.020f);
  float wall_m = 0.002f;
  Eigen::Vector3f block_min = Eigen::Vector3f(-0.017f, -0.008f, 0.0005f);  ///< particle block
  Eigen::Vector3f block_max = Eigen::Vector3f(0.017f, 0.008f, 0.012f);
  Eigen::Vector3f blade_center = Eigen::Vector3f(-0.004f, 0.0f, 0.024f);   ///< prism instrument
  Eigen::Vector3f blade_half = Eigen::Vector3f(0.004f, 0.002f, 0.005f);
  float shaft_length_m = 0.035f;
  Eigen::Vector3f zone_center = Eigen::Vector3f(0.013f, 0.0f, 0.016f);     ///< danger zone
  float zone_radius_m = 0.005f;
};

/// Builds the sample scene with about `particle_count` particles filling the block on a cubic
/// lattice (exactly `particle_count` when it is at least 8), and a camera framing it for an
/// image of aspect `aspect` (width / height). Mesh 0..4 are the walls, 5 the instrument,
/// 6 the danger zone.
RenderScene make_sample_scene(int particle_count, float aspect = 16.0f / 9.0f,
                              const SampleSceneLayout& layout = SampleSceneLayout(),
                              const SampleSceneColors& colors = SampleSceneColors());

}  // namespace acdr

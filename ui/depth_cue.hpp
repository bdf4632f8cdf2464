// Depth cues for a trainee without a haptic device, who cannot feel where the material starts:
//  - a drop line from the instrument's working tip straight down to the work's surface, with a
//    ring where it meets the surface and another at the deepest safe level, drawn over the
//    scene so the tip's height above (or depth below) the surface reads in any camera angle;
//  - a depth gauge: a vertical scale from above the surface to below the deepest safe level
//    with the tip on it, and the depth in millimetres in words.
// "Down" is the world's -z: the surgeon works from above in every bundled module. For the
// C4-C5 segment the surface is the front of the vertebral bodies (the anterior face of the
// disc) and the deepest safe level their back wall, where the posterior longitudinal ligament
// and the spinal cord lie; for other scenes, the top and the bottom of the material.
#pragma once

#include <string>

#include <imgui.h>

#include "app/world_state.hpp"
#include "engine/core/frame.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

/// The levels a depth is measured against, fixed for a scene.
struct DepthReference {
  bool valid = false;
  double surface_z_m = 0.0;  ///< depth 0
  double floor_z_m = 0.0;    ///< the deepest safe level (below the surface)
  std::string surface_name;  ///< "front of the disc"
  std::string floor_name;    ///< "back of the disc (PLL, spinal cord)"
};

/// The reference of `world`: its anatomy's landmarks, else the extent of the material in
/// `initial` (the state before anything moved); invalid when the scene has neither.
DepthReference depth_reference(const World& world, const WorldState& initial);

/// Where the tip is against the reference.
struct DepthCue {
  bool valid = false;
  Vec3 tip_m = Vec3::Zero();
  double depth_m = 0.0;     ///< below the surface (negative: above it)
  double to_floor_m = 0.0;  ///< above the deepest safe level (negative: beyond it)
  DepthReference reference;
};

DepthCue make_depth_cue(const DepthReference& reference, const Frame& frame);

/// "4.2 mm in, 9.1 mm to the back of the disc (PLL, spinal cord)", or "3.0 mm above the front
/// of the disc".
std::string depth_text(const DepthCue& cue);

/// The drop line and its rings, drawn on ImGui's background draw list (over the scene, under
/// the HUD windows) through `camera` for a display of `display` pixels.
void draw_depth_drop_line(const DepthCue& cue, const RenderCamera& camera, const ImVec2& display);

/// The depth gauge, a window at the display's bottom right.
void draw_depth_gauge(const DepthCue& cue, const ImVec2& display);

}  // namespace acdr

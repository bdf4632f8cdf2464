// Turns the state of a World into a RenderScene: static solids, the instrument and the
// particles, coloured by material and by whether they have been removed.
#pragma once

#include <cstdint>
#include <vector>

#include "app/world_state.hpp"
#include "engine/world/world.hpp"
#include "ui/material_surfaces.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

/// Colours of the scene (RGBA).
struct SceneStyle {
  Eigen::Vector4f wall{0.55f, 0.63f, 0.75f, 0.35f};  ///< translucent, so the nucleus shows
  Eigen::Vector4f instrument{0.72f, 0.74f, 0.78f, 1.0f};
  Eigen::Vector4f nucleus{0.93f, 0.80f, 0.45f, 1.0f};
  Eigen::Vector4f annulus{0.90f, 0.88f, 0.84f, 1.0f};  ///< pearly white
  Eigen::Vector4f cartilage{0.74f, 0.82f, 0.90f, 1.0f};  ///< endplate cartilage, bluish white
  Eigen::Vector4f removed{0.95f, 0.42f, 0.22f, 1.0f};  ///< material that left the removal region
  Eigen::Vector4f bone{0.90f, 0.86f, 0.74f, 1.0f};
  /// The posterior longitudinal ligament behind the disc space: silvery white fibre.
  Eigen::Vector4f ligament{0.80f, 0.82f, 0.86f, 1.0f};
  Eigen::Vector4f artery{0.85f, 0.12f, 0.12f, 0.55f};   ///< vertebral arteries, translucent
  Eigen::Vector4f nerve{0.98f, 0.86f, 0.20f, 0.55f};    ///< nerve roots
  Eigen::Vector4f cord{0.35f, 0.55f, 0.95f, 0.30f};     ///< spinal cord / PLL
  Eigen::Vector4f zone{0.95f, 0.35f, 0.80f, 0.35f};     ///< other declared zones
  /// A zone the instrument is within the warning distance of, and one it is inside.
  Eigen::Vector4f zone_warning{1.00f, 0.62f, 0.05f, 0.60f};
  Eigen::Vector4f zone_inside{1.00f, 0.05f, 0.05f, 0.80f};
  /// Off for an atlas picture of the anatomy alone (no instrument, no tray or walls; the
  /// ligament is anatomy and stays).
  bool draw_instrument = true;
  bool draw_walls = true;
};

/// How the particle materials are turned into geometry.
struct SnapshotOptions {
  MaterialDrawing drawing = MaterialDrawing::kSurfaces;
  /// Keeps surfaces between the frames of a live view (null: extracted every time).
  MaterialSurfaceCache* cache = nullptr;
};

/// The scene as it is now, framed by a default camera for an image of the given aspect.
RenderScene snapshot_world(const World& world, float aspect, const SceneStyle& style = {},
                           const SnapshotOptions& options = {});

/// The scene of a captured state: constant parts from `world` (safe to read while another
/// thread steps it), moving parts from `state`.
RenderScene snapshot_state(const World& world, const WorldState& state, float aspect,
                           const SceneStyle& style = {}, const SnapshotOptions& options = {});

}  // namespace acdr

// The peer: the same nucleus built as a Bullet soft body (btSoftBody with volumetric links:
// one node per particle, one link per bond, the same lattice, masses and static walls), moved
// through by the instrument along a recorded path, so its force and removal can be compared
// with ours on the same axes.
//
// How the peer is configured (fairly, and said so in docs/performance.md):
//  - millimetre world units (Bullet's defaults, a 0.25 collision margin and sparse-SDF
//    voxel, are then 0.25 mm instead of 0.25 m); soft-body margin = our contact distance h/2,
//    set before any node is added; rigid shapes' margins 0.01 mm;
//  - double-precision Bullet (the single-precision build misjudges node-box distances at this
//    scale, docs/dependencies.md);
//  - position iterations swept (the knob Bullet's soft bodies trade accuracy for time with);
//    link stiffness kLST and velocity damping kDP given per point;
//  - the instrument is a heavy (1000 kg) body without gravity and without contact to the
//    walls, placed on the path every step with the path's velocity; the force on it is its
//    momentum change from the soft-body contact impulses over the step.
#pragma once

#include <vector>

#include "bench/scene_run.hpp"

namespace acdr {

struct PeerSettings {
  double dt_s = 1e-3;
  int position_iterations = 4;  ///< btSoftBody::Config::piterations
  double link_stiffness = 1.0;  ///< kLST, (0, 1]
  double damping = 0.0;         ///< kDP, [0, 1]
};

/// Runs the peer over `window` with the instrument following `path`: path[k] is the grip pose
/// at (k + 1) * window.sample_s after the start (a reference run's `instrument`), and `start`
/// the pose at the start; poses in between are interpolated. Gives the same figures as
/// run_scene (force windows, removed fraction, times).
RunTrace run_bullet_peer(const WorldConfig& config, const Pose& start,
                         const std::vector<Pose>& path, const RunWindow& window,
                         const PeerSettings& settings,
                         const std::function<void(double)>& progress = {});

}  // namespace acdr

// The trainee view's bone stress view: while it is on, the vertebrae are drawn from their
// finite-element surfaces, coloured in bands by the von Mises stress of the newest sample the
// bone's solver thread solved in full (BoneStressWorker::latest_field, about ten a second),
// with a legend in MPa. The scale only grows during an attempt (the largest stress shown so
// far, rounded up), so a colour means the same stress from one moment to the next.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <imgui.h>

#include "app/bone_stress_worker.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

class LiveBoneStress {
 public:
  /// Takes the worker's newest field when it is newer than the one shown; rebuilds the meshes.
  void update(BoneStressWorker& worker);
  bool has_field() const { return shown_ > 0; }
  /// Replaces the scene's meshes whose geometry id is in `bone_ids` (the anatomy's vertebrae)
  /// by the coloured ones (the plain bone stays until a first field arrives).
  void apply(RenderScene& scene, std::span<const std::uint64_t> bone_ids) const;
  /// The legend and the time of the field shown, at the right edge below `top` (the bottom of
  /// the HUD's status window, so the two never overlap).
  void draw_legend(const ImVec2& display, float top) const;

  static constexpr int kBands = 12;

 private:
  std::uint64_t seen_ = 0;   // version of the worker's field read last
  std::uint64_t shown_ = 0;  // fields turned into meshes (part of their geometry ids)
  BoneStressField field_;
  std::vector<RenderMesh> meshes_;
  double top_Pa_ = 0.0;   // top of the colour scale
  double peak_Pa_ = 0.0;  // the largest element stress of the field shown
};

}  // namespace acdr

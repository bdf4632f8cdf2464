// A picture of a vertebra's stress under a set of loads: its surface coloured by von Mises
// stress in bands (a contour plot), the loads as arrows, and the displacement as arrows scaled
// up to be seen; with the colour bar, its unit and what was loaded, drawn by ImGui. For
// `acdr render --stress` (and anything else that has a solved BoneSegment sample).
#pragma once

#include <span>
#include <string>

#include "engine/bone/bone_segment.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

struct BoneStressView {
  RenderScene scene;
  int vertebra = 1;                  ///< the vertebra drawn (0 C4, 1 C5): the more stressed one
  double scale_max_Pa = 0.0;         ///< top of the colour bar
  double peak_Pa = 0.0;              ///< largest element von Mises stress of the vertebra
  double max_displacement_m = 0.0;
  double arrow_scale = 0.0;          ///< displacement arrows are this many times the displacement
  double load_N = 0.0;               ///< sum of the load magnitudes on the vertebra drawn
  int bands = 12;
};

/// Builds the view of the more stressed vertebra of a sample solved into `scratch` (by
/// BoneSegment::solve with `loads`), framed from its disc side. `scale_max_Pa` <= 0: the bar
/// ends at the peak, rounded up.
BoneStressView bone_stress_view(const BoneSegment& bone, const BoneSegmentScratch& scratch,
                                const BoneSampleResult& result,
                                std::span<const BoneLoadPoint> loads, float aspect,
                                double scale_max_Pa = 0.0);

/// The colour of a stress at `fraction` of the bar (0..1): blue, cyan, green, yellow, red.
Eigen::Vector4f stress_color(double fraction);

/// Draws the colour bar (MPa), the caption lines and the arrow scale as ImGui windows over the
/// picture (call inside an ImGui frame).
void draw_bone_stress_overlay(const BoneStressView& view, const std::string& caption);

/// Renders `view` with its overlay to a PNG of width x height.
bool render_bone_stress_png(const BoneStressView& view, const std::string& caption, int width,
                            int height, const std::string& path, std::string* error);

}  // namespace acdr

// Pictures of the C4-C5 segment as an anatomy atlas shows it: from the front (the surgeon's
// view down the approach) or from the side, with the parts a surgeon names labelled.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/world/world.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

enum class AnatomyView {
  kSurgeon,   ///< the default picture: from anterior, a little left and caudal, on the disc space
  kAnterior,  ///< straight from the front (+z), the whole segment, the patient's left on the right
  kLateral,   ///< straight from the patient's left (+x), anterior on the left
};

/// "surgeon", "anterior" or "lateral"; false for anything else.
bool parse_anatomy_view(const std::string& text, AnatomyView* view);

/// A camera for `view` framing both vertebrae with their processes (kSurgeon: the disc space,
/// as snapshot_world frames it).
RenderCamera anatomy_camera(const Anatomy& anatomy, AnatomyView view, float aspect);

/// A label: its text, the point it names (segment frame, m), and which side of the picture its
/// text goes (-1 left, +1 right).
struct AnatomyLabel {
  std::string text;
  Eigen::Vector3f point_m = Eigen::Vector3f::Zero();
  int column = -1;
};

/// The parts seen in `view` (kAnterior or kLateral; none for kSurgeon): the bones' parts
/// (segment_part_points), the disc (annulus, nucleus, window, cartilage endplate) and the
/// structures at risk (vertebral artery, nerve root, spinal cord).
std::vector<AnatomyLabel> anatomy_labels(const World& world, AnatomyView view);

/// Draws the labels over the picture with ImGui: each text in a column at the picture's edge,
/// a leader line to its point (projected through `camera`). Call inside an ImGui frame.
void draw_anatomy_labels(const std::vector<AnatomyLabel>& labels, const RenderCamera& camera,
                         int width, int height, const std::string& caption);

/// `scene` with its labels, written as an RGB PNG.
bool render_labelled_png(const RenderScene& scene, const std::vector<AnatomyLabel>& labels,
                         const std::string& caption, int width, int height,
                         const std::string& path, std::string* error);

}  // namespace acdr

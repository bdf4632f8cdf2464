// Anterior and lateral pictures of the segment, and their labels.
#include "ui/anatomy_view.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <imgui.h>

#include "app/world_state.hpp"
#include "ui/imgui_offscreen.hpp"
#include "ui/png_writer.hpp"
#include "ui/render_camera.hpp"

namespace acdr {
namespace {

constexpr float kPi = 3.14159265358979f;

Eigen::Vector3f f3(const Vec3& v) { return v.cast<float>(); }

}  // namespace

bool parse_anatomy_view(const std::string& text, AnatomyView* view) {
  if (text == "surgeon") *view = AnatomyView::kSurgeon;
  else if (text == "anterior") *view = AnatomyView::kAnterior;
  else if (text == "lateral") *view = AnatomyView::kLateral;
  else return false;
  return true;
}

RenderCamera anatomy_camera(const Anatomy& anatomy, AnatomyView view, float aspect) {
  const SegmentLandmarks& l = anatomy.landmarks();
  const SegmentParams& p = anatomy.config().segment;
  // The segment's extent: both bodies with the uncinate processes, the transverse processes,
  // and back to the spinous processes.
  const double x = std::abs(l.foramen_transversarium_m[0].x()) + l.foramen_radius_m +
                   std::max(p.c4.transverse_process_reach_m, p.c5.transverse_process_reach_m) + 1e-3;
  const double y_top = 0.5 * p.disc_height_m + p.c4.body_height_m + 1e-3;
  const double y_bottom = -0.5 * p.disc_height_m - p.c5.body_height_m - 2e-3;
  const double z_back = l.canal_back_z_m - 2.0 * p.c4.lamina_thickness_m - p.c4.spinous_process_length_m - 2e-3;
  const double z_front = l.body_front_z_m + 1e-3;
  RenderCamera camera;
  camera.fov_y_deg = 30.0f;
  camera.up = Eigen::Vector3f(0, 1, 0);
  camera.target = Eigen::Vector3f(0.0f, static_cast<float>(0.5 * (y_top + y_bottom)),
                                  static_cast<float>(0.5 * (z_front + z_back)));
  // Half extents across the picture and the depth toward the eye.
  double across = 0.0, depth = 0.0;
  Eigen::Vector3f back;
  if (view == AnatomyView::kLateral) {
    back = Eigen::Vector3f(1, 0, 0);
    across = 0.5 * (z_front - z_back);
    depth = x;
  } else {
    back = Eigen::Vector3f(0, 0, 1);
    across = x;
    depth = 0.5 * (z_front - z_back);
    if (view == AnatomyView::kAnterior) {
      // The bodies and processes, not the spinous tips behind them: centre on the canal.
      camera.target.z() = static_cast<float>(l.body_back_z_m);
    }
  }
  const double up_half = 0.5 * (y_top - y_bottom);
  const double tan_y = std::tan(0.5 * camera.fov_y_deg * kPi / 180.0);
  // Room for the label columns at the sides (a third of the picture's width).
  const double tan_x = tan_y * aspect * 0.62;
  const double distance = std::max(across / tan_x, up_half / tan_y) * 1.08 + depth;
  camera.eye = camera.target + back * static_cast<float>(distance);
  camera.near_m = static_cast<float>(std::max(1e-3, distance - 2.5 * depth - 0.02));
  camera.far_m = static_cast<float>(distance + 2.5 * depth + 0.2);
  return camera;
}

std::vector<AnatomyLabel> anatomy_labels(const World& world, AnatomyView view) {
  std::vector<AnatomyLabel> labels;
  const Anatomy* anatomy = world.anatomy();
  if (!anatomy || view == AnatomyView::kSurgeon) return labels;
  const SegmentParams& p = anatomy->config().segment;
  const SegmentLandmarks& l = anatomy->landmarks();
  const bool anterior = view == AnatomyView::kAnterior;
  // Anterior: the patient's right (-x) is on the picture's left; lateral: from the left (+x),
  // anterior (+z) on the picture's left, as a lateral radiograph is shown.
  const double side = anterior ? -1.0 : 1.0;
  const std::vector<std::string> anterior_parts = {
      "C4 vertebral body", "C5 vertebral body", "C4 anterior lip", "C5 uncinate process",
      "C4 anterior tubercle", "C5 anterior tubercle", "C5 superior endplate (saddle)"};
  const std::vector<std::string> lateral_parts = {
      "C4 vertebral body", "C5 vertebral body", "C4 anterior lip", "C4 pedicle",
      "C5 anterior tubercle", "C5 posterior tubercle", "C4 lateral mass", "C5 lateral mass",
      "facet joint", "C4 lamina", "C5 spinous process (bifid)", "C4 spinous process (bifid)"};
  const std::vector<std::string>& wanted = anterior ? anterior_parts : lateral_parts;
  for (const PartPoint& part : segment_part_points(p, side)) {
    if (std::find(wanted.begin(), wanted.end(), part.name) == wanted.end()) continue;
    AnatomyLabel label{part.name, f3(part.point_m), -1};
    if (!anterior) label.column = part.point_m.z() > l.body_back_z_m ? -1 : 1;
    labels.push_back(label);
  }
  // The disc, from the particles: the nucleus seen through the anterior window (its front-most
  // particle) and the annulus beside the window.
  WorldState state;
  capture_world_state(world, state);
  int nucleus = -1, annulus = -1;
  for (std::size_t i = 0; i < state.positions.size(); ++i) {
    const Eigen::Vector3f& x = state.positions[i];
    const ParticleClass c = state.particle_class[i];
    if (c == ParticleClass::kTarget && std::abs(x.x()) < 1e-3f && std::abs(x.y()) < 1e-3f &&
        (nucleus < 0 || x.z() > state.positions[nucleus].z()))
      nucleus = static_cast<int>(i);
    const float ax = anterior ? 0.55f : -0.0f;
    if (c == ParticleClass::kProtected && std::abs(x.y()) < 1e-3f &&
        (anterior ? x.x() > ax * static_cast<float>(l.endplate_half_width_m) : x.x() > 0.0f) &&
        (annulus < 0 || x.z() > state.positions[annulus].z()))
      annulus = static_cast<int>(i);
  }
  const int front = anterior ? 1 : -1;  // the column on the anterior side
  if (nucleus >= 0) labels.push_back({"nucleus pulposus (anterior window)", state.positions[nucleus], front});
  if (annulus >= 0) labels.push_back({"annulus fibrosus", state.positions[annulus], front});
  if (anterior && nucleus >= 0) {
    Eigen::Vector3f c = state.positions[nucleus];
    c.y() = static_cast<float>(l.c5_upper_endplate_y_m + 0.4e-3);
    labels.push_back({"cartilage endplate", c, 1});
  }
  const int left = 0;  // +x, the side the lateral picture and the anterior right column show
  const Vec3 ft = l.foramen_transversarium_m[left];
  labels.push_back({anterior ? "vertebral artery (foramen transversarium)" : "vertebral artery",
                    f3(Vec3(ft.x(), 0.0, ft.z())), front});
  labels.push_back({anterior ? "exiting nerve root (C5)" : "nerve root, intervertebral foramen",
                    f3(l.nerve_root_m[left][2]), 1});
  if (!anterior) {
    labels.push_back({"spinal canal and cord", f3(Vec3(0.0, 0.5 * l.c5_upper_endplate_y_m - 8e-3,
                                                       0.5 * (l.body_back_z_m + l.canal_back_z_m))), 1});
    // The ligament the disc's particles meet (world.anatomy.posterior_ligament): a point on its
    // face in its upper part, which the exiting root does not hide from the left.
    for (const Collider& c : world.static_colliders())
      if (c.particles_only && c.kind == ColliderKind::kBox)
        labels.push_back({"posterior longitudinal ligament",
                          f3(c.pose.position + Vec3(0.0, 0.75 * c.half_extents_m.y(),
                                                    c.half_extents_m.z())), 1});
  }
  return labels;
}

void draw_anatomy_labels(const std::vector<AnatomyLabel>& labels, const RenderCamera& camera,
                         int width, int height, const std::string& caption) {
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  const float line_h = ImGui::GetTextLineHeight() + 5.0f;
  for (int column : {-1, 1}) {
    struct Placed {
      const AnatomyLabel* label;
      Eigen::Vector2f anchor;
      float y;
    };
    std::vector<Placed> placed;
    for (const AnatomyLabel& label : labels) {
      if (label.column != column) continue;
      const auto px = project_to_pixel(camera, width, height, label.point_m);
      if (!px) continue;
      placed.push_back({&label, *px, (*px).y()});
    }
    std::sort(placed.begin(), placed.end(), [](const Placed& a, const Placed& b) { return a.y < b.y; });
    // Spread the texts down the column so that none overlaps the one above it.
    float next = 40.0f;
    for (Placed& p : placed) {
      p.y = std::max(p.y, next);
      next = p.y + line_h;
    }
    const float overflow = next - (height - 10.0f);
    if (overflow > 0.0f)
      for (Placed& p : placed) p.y -= overflow;
    for (const Placed& p : placed) {
      const char* text = p.label->text.c_str();
      const ImVec2 size = ImGui::CalcTextSize(text);
      const float tx = column < 0 ? 12.0f : width - 12.0f - size.x;
      const float ty = p.y - 0.5f * size.y;
      const float lx = column < 0 ? tx + size.x + 4.0f : tx - 4.0f;
      dl->AddRectFilled(ImVec2(tx - 3.0f, ty - 1.0f), ImVec2(tx + size.x + 3.0f, ty + size.y + 1.0f),
                        IM_COL32(20, 22, 28, 200));
      dl->AddText(ImVec2(tx, ty), IM_COL32(240, 240, 240, 255), text);
      dl->AddLine(ImVec2(lx, p.y), ImVec2(p.anchor.x(), p.anchor.y()), IM_COL32(255, 230, 120, 230), 1.5f);
      dl->AddCircleFilled(ImVec2(p.anchor.x(), p.anchor.y()), 3.0f, IM_COL32(255, 230, 120, 255));
    }
  }
  if (!caption.empty()) {
    const ImVec2 size = ImGui::CalcTextSize(caption.c_str());
    dl->AddText(ImVec2(0.5f * (width - size.x), 10.0f), IM_COL32(240, 240, 240, 255), caption.c_str());
  }
}

bool render_labelled_png(const RenderScene& scene, const std::vector<AnatomyLabel>& labels,
                         const std::string& caption, int width, int height,
                         const std::string& path, std::string* error) {
  auto ui = ImGuiOffscreen::create(width, height, error);
  if (!ui) return false;
  std::vector<std::uint8_t> rgb;
  if (!ui->render(&scene, [&] { draw_anatomy_labels(labels, scene.camera, width, height, caption); },
                  &rgb, error))
    return false;
  return write_png_rgb(path, width, height, rgb, error);
}

}  // namespace acdr

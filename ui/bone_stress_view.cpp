// The stress picture of a vertebra: see bone_stress_view.hpp.
#include "ui/bone_stress_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "ui/imgui_offscreen.hpp"
#include "ui/mesh_primitives.hpp"
#include "ui/png_writer.hpp"
#include "ui/render_camera.hpp"

namespace acdr {
namespace {

/// A closed cone from base centre `a` (radius r) to apex `b`.
RenderMesh make_cone(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float r,
                     const Eigen::Vector4f& rgba, int segments = 16) {
  RenderMesh m;
  m.rgba = rgba;
  const Eigen::Vector3f axis = (b - a).normalized();
  const Eigen::Vector3f u = axis.unitOrthogonal();
  const Eigen::Vector3f v = axis.cross(u);
  m.vertices.push_back(b);  // 0 apex
  m.vertices.push_back(a);  // 1 base centre
  for (int i = 0; i < segments; ++i) {
    const float t = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / static_cast<float>(segments);
    m.vertices.push_back(a + r * (std::cos(t) * u + std::sin(t) * v));
  }
  for (int i = 0; i < segments; ++i) {
    const std::uint32_t p = 2 + i, q = 2 + (i + 1) % segments;
    m.indices.insert(m.indices.end(), {0u, p, q});
    m.indices.insert(m.indices.end(), {1u, q, p});
  }
  return m;
}

void add_arrow(RenderScene& scene, const Eigen::Vector3f& from, const Eigen::Vector3f& to,
               float radius, const Eigen::Vector4f& rgba) {
  const Eigen::Vector3f d = to - from;
  const float len = d.norm();
  if (!(len > 4.0f * radius)) return;
  const Eigen::Vector3f neck = to - d * (3.0f * radius / len);
  RenderMesh shaft = make_cylinder(from, neck, radius, rgba, 12);
  append_mesh(shaft, make_cone(neck, to, 2.2f * radius, rgba));
  shaft.specular = 0.3f;
  shaft.include_in_framing = false;
  scene.meshes.push_back(std::move(shaft));
}

/// A bar top rounded up to 1, 2 or 5 times a power of ten.
double nice_ceiling(double x) {
  if (!(x > 0.0)) return 1.0;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= x * (1.0 - 1e-9)) return m * p;
  return 10.0 * p;
}

}  // namespace

Eigen::Vector4f stress_color(double f) {
  f = std::clamp(f, 0.0, 1.0);
  // Piecewise linear through blue, cyan, green, yellow, red (the usual FE contour palette).
  static const float kStops[5][3] = {{0.15f, 0.25f, 0.85f}, {0.10f, 0.75f, 0.90f},
                                     {0.20f, 0.80f, 0.25f}, {0.95f, 0.85f, 0.15f},
                                     {0.90f, 0.15f, 0.10f}};
  const double x = f * 4.0;
  const int i = std::min(3, static_cast<int>(x));
  const float t = static_cast<float>(x - i);
  Eigen::Vector4f c;
  for (int k = 0; k < 3; ++k) c[k] = (1.0f - t) * kStops[i][k] + t * kStops[i + 1][k];
  c[3] = 1.0f;
  return c;
}

BoneStressView bone_stress_view(const BoneSegment& bone, const BoneSegmentScratch& scratch,
                                const BoneSampleResult& result,
                                std::span<const BoneLoadPoint> loads, float aspect,
                                double scale_max_Pa) {
  BoneStressView view;
  // The vertebra drawn: the solved one with the larger stress.
  double best = -1.0;
  for (int v = 0; v < 2; ++v) {
    if (!result.solved[v]) continue;
    const auto& vm = scratch.solution[v].element_von_mises_Pa;
    const double peak = vm.empty() ? 0.0 : *std::max_element(vm.begin(), vm.end());
    if (peak > best) best = peak, view.vertebra = v;
  }
  const BoneFem& fem = bone.vertebra(view.vertebra);
  const bool solved = result.solved[view.vertebra];
  const BoneSolution& sol = scratch.solution[view.vertebra];
  view.peak_Pa = std::max(0.0, best);
  view.scale_max_Pa = scale_max_Pa > 0.0 ? scale_max_Pa : nice_ceiling(view.peak_Pa * 1e-6) * 1e6;

  // The surface in bands: each boundary face takes the stress of its tetrahedron (in the shell
  // the shell's own stress), so the colours reach the peak the caption gives.
  const TetMesh& mesh = fem.mesh();
  const auto& faces = fem.surface().faces();
  std::vector<RenderMesh> bands(view.bands);
  for (int b = 0; b < view.bands; ++b) {
    bands[b].rgba = stress_color((b + 0.5) / view.bands);
    bands[b].specular = 0.12f;
  }
  for (const BoundaryFace& f : faces) {
    const double s = solved ? sol.element_von_mises_Pa[f.tet] : 0.0;
    const int b = std::clamp(static_cast<int>(s / view.scale_max_Pa * view.bands), 0, view.bands - 1);
    RenderMesh& m = bands[b];
    for (std::uint32_t n : f.nodes) {
      m.indices.push_back(static_cast<std::uint32_t>(m.vertices.size()));
      m.vertices.push_back(mesh.nodes[n].cast<float>());
    }
  }
  for (RenderMesh& m : bands)
    if (!m.indices.empty()) view.scene.meshes.push_back(std::move(m));

  // Displacement arrows at up to 40 surface nodes, largest first, at least 2 mm apart.
  if (solved) {
    std::vector<std::uint32_t> nodes;
    for (std::uint32_t i = 0; i < mesh.nodes.size(); ++i)
      if (fem.surface().on_surface()[i]) nodes.push_back(i);
    std::sort(nodes.begin(), nodes.end(), [&](std::uint32_t a, std::uint32_t b) {
      return sol.displacement_m[a].squaredNorm() > sol.displacement_m[b].squaredNorm();
    });
    view.max_displacement_m = nodes.empty() ? 0.0 : sol.displacement_m[nodes[0]].norm();
    if (view.max_displacement_m > 0.0) {
      view.arrow_scale = 3.0e-3 / view.max_displacement_m;  // the largest drawn 3 mm long
      std::vector<Vec3> placed;
      for (std::uint32_t n : nodes) {
        if (placed.size() >= 40) break;
        const Vec3& p = mesh.nodes[n];
        const Vec3 d = sol.displacement_m[n] * view.arrow_scale;
        if (d.norm() < 0.6e-3) break;  // the rest are too small to read
        bool near = false;
        for (const Vec3& q : placed) near = near || (q - p).norm() < 2.0e-3;
        if (near) continue;
        placed.push_back(p);
        // Ending at the node: an indented surface moves inward, and an arrow starting there
        // would be hidden inside the bone.
        add_arrow(view.scene, (p - d).cast<float>(), p.cast<float>(), 0.15e-3f,
                  Eigen::Vector4f(0.97f, 0.97f, 0.99f, 1.0f));
      }
    }
  }
  // The loads on this vertebra: dark arrows pointing at their points, 1 mm per newton (2-8 mm).
  for (const BoneLoadPoint& p : loads) {
    if (p.vertebra != view.vertebra) continue;
    const Eigen::Vector3f f = p.force_N;
    view.load_N += f.norm();
    if (!(f.norm() > 0.0f)) continue;
    const float len = std::clamp(1e-3f * f.norm(), 2e-3f, 8e-3f);
    add_arrow(view.scene, p.point_m - f.normalized() * len, p.point_m, 0.25e-3f,
              Eigen::Vector4f(0.15f, 0.15f, 0.18f, 1.0f));
  }

  // Framed from the disc side: above and in front of C5, below and in front of C4.
  const VertebraBodyFrame& body = fem.body();
  const Eigen::Vector3f c = body.center_m.cast<float>();
  const float side = view.vertebra == 0 ? -1.0f : 1.0f;
  const Eigen::Vector3f half(static_cast<float>(body.half_width_m) + 6e-3f,
                             static_cast<float>(body.half_height_m) + 2e-3f, 16e-3f);
  view.scene.camera = frame_bounds(c - half, c + half, aspect, Eigen::Vector3f(0.3f, side * 1.0f, 0.6f));
  view.scene.camera.up = Eigen::Vector3f(0.0f, 0.0f, 1.0f);
  view.scene.ground.visible = false;
  view.scene.shadows.particles_cast = false;
  return view;
}

void draw_bone_stress_overlay(const BoneStressView& view, const std::string& caption) {
  const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                                 ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize;
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  // The colour bar, right side: bands from 0 (bottom) to the scale's top.
  const float bar_h = std::min(360.0f, display.y * 0.55f), bar_w = 26.0f;
  ImGui::SetNextWindowPos(ImVec2(display.x - 150.0f, 20.0f));
  ImGui::Begin("Stress scale", nullptr, fixed);
  ImGui::TextUnformatted("von Mises");
  ImGui::TextUnformatted("stress (MPa)");
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  for (int b = 0; b < view.bands; ++b) {
    const Eigen::Vector4f c = stress_color((b + 0.5) / view.bands);
    const float y1 = p0.y + bar_h * (1.0f - static_cast<float>(b) / view.bands);
    const float y0 = p0.y + bar_h * (1.0f - static_cast<float>(b + 1) / view.bands);
    dl->AddRectFilled(ImVec2(p0.x, y0), ImVec2(p0.x + bar_w, y1),
                      ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], 1.0f)));
  }
  for (int t = 0; t <= 4; ++t) {
    const float y = p0.y + bar_h * (1.0f - t / 4.0f);
    char label[32];
    std::snprintf(label, sizeof label, "%.3g", view.scale_max_Pa * 1e-6 * t / 4.0);
    dl->AddLine(ImVec2(p0.x + bar_w, y), ImVec2(p0.x + bar_w + 5.0f, y), IM_COL32(230, 230, 230, 255));
    dl->AddText(ImVec2(p0.x + bar_w + 8.0f, y - 8.0f), IM_COL32(230, 230, 230, 255), label);
  }
  ImGui::Dummy(ImVec2(bar_w + 70.0f, bar_h + 6.0f));
  ImGui::End();

  ImGui::SetNextWindowPos(ImVec2(20.0f, 20.0f));
  ImGui::Begin("Stress caption", nullptr, fixed);
  ImGui::TextUnformatted(caption.c_str());
  ImGui::Text("%s: peak %.2f MPa (any element) under %.2f N", view.vertebra == 0 ? "C4" : "C5",
              view.peak_Pa * 1e-6, view.load_N);
  ImGui::Text("largest displacement %.2f um; white arrows x%.0f", view.max_displacement_m * 1e6,
              view.arrow_scale);
  ImGui::TextUnformatted("dark arrows: loads on the bone");
  ImGui::End();
}

bool render_bone_stress_png(const BoneStressView& view, const std::string& caption, int width,
                            int height, const std::string& path, std::string* error) {
  auto ui = ImGuiOffscreen::create(width, height, error);
  if (!ui) return false;
  std::vector<std::uint8_t> rgb;
  if (!ui->render(&view.scene, [&] { draw_bone_stress_overlay(view, caption); }, &rgb, error))
    return false;
  return write_png_rgb(path, width, height, rgb, error);
}

}  // namespace acdr

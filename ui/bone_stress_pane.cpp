// The drill-down's bone stress pane: see bone_stress_pane.hpp.
#include "ui/bone_stress_pane.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include <imgui.h>

#include "ui/bone_stress_view.hpp"
#include "ui/word_wrap.hpp"

namespace acdr {
namespace {

// Which way each vertebra's disc side faces: down for C4 (its lower endplate), up for C5.
double disc_side(int vertebra) { return vertebra == 0 ? -1.0 : 1.0; }

// A face is drawn when it faces the disc at least this much (the cosine to the vertical).
constexpr double kFacing = 0.2;

BoneMeasure endplate_measure(int vertebra) {
  return vertebra == 0 ? BoneMeasure::kC4InferiorEndplate : BoneMeasure::kC5SuperiorEndplate;
}

}  // namespace

double nice_stress_top(double peak_Pa) {
  const double x = peak_Pa * 1e-6;  // MPa
  if (!(x > 0.0)) return 1e6;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= x * (1.0 - 1e-9)) return m * p * 1e6;
  return 10.0 * p * 1e6;
}

std::unique_ptr<BoneStressPane> BoneStressPane::create(const ScenarioModel& scenario,
                                                       const AttemptRecording& recording,
                                                       std::string* why) {
  if (!scenario.bone.enabled) {
    *why = "the module's scenario does not model the bone";
    return nullptr;
  }
  if (recording.bone_loads.empty()) {
    *why = "the recording has no bone load samples";
    return nullptr;
  }
  std::unique_ptr<BoneStressPane> pane(new BoneStressPane());
  pane->bone_ = pane->replay_.bone(scenario, why);
  if (!pane->bone_) {
    *why = "bone model: " + *why;
    return nullptr;
  }
  pane->samples_ = recording.bone_loads;
  pane->scratch_.nodal_fields = true;  // every element's stress, not only the measured ones
  for (const BoneLoadRecord& r : pane->samples_) {
    double sum = 0.0;
    for (const BoneLoadPoint& p : r.points) sum += p.force_N.cast<double>().norm();
    if (sum > pane->peak_load_N_) {
      pane->peak_load_N_ = sum;
      pane->peak_load_t_s_ = r.t_s;
    }
  }
  // The disc-side surface of each vertebra, far faces first.
  for (int v = 0; v < 2; ++v) {
    const BoneFem& fem = pane->bone_->vertebra(v);
    const auto& faces = fem.surface().faces();
    const auto& nodes = fem.mesh().nodes;
    const double side = disc_side(v);
    std::vector<std::uint32_t> kept;
    for (std::uint32_t f = 0; f < faces.size(); ++f)
      if (side * fem.surface().face_normal(f).y() > kFacing) kept.push_back(f);
    auto height = [&](std::uint32_t f) {
      const auto& n = faces[f].nodes;
      return side * (nodes[n[0]].y() + nodes[n[1]].y() + nodes[n[2]].y());
    };
    std::sort(kept.begin(), kept.end(),
              [&](std::uint32_t a, std::uint32_t b) { return height(a) < height(b); });
    EndplateSurface& s = pane->surfaces_[v];
    s.vertebra = v;
    for (std::uint32_t f : kept) {
      const auto& n = faces[f].nodes;
      s.triangles.push_back({nodes[n[0]], nodes[n[1]], nodes[n[2]]});
      pane->face_tets_[v].push_back(faces[f].tet);
    }
    s.stress_Pa.assign(s.triangles.size(), 0.0);
  }
  return pane;
}

void BoneStressPane::set_scale_top(double top_Pa) { scale_top_Pa_ = nice_stress_top(top_Pa); }

void BoneStressPane::show_time(double t_s) {
  // The last sample at or before t (the first one before any); a microsecond of slack, so a
  // time read from a sample (the peak's) finds that sample.
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t_s + 1e-6,
                                   [](double t, const BoneLoadRecord& r) { return t < r.t_s; });
  const long index = it == samples_.begin() ? 0 : static_cast<long>(it - samples_.begin()) - 1;
  if (index == solved_index_) return;
  solved_index_ = index;
  const BoneLoadRecord& r = samples_[static_cast<std::size_t>(index)];
  const BoneSampleResult result = bone_->solve(r.t_s, r.points, scratch_);
  sample_t_s_ = r.t_s;
  sample_load_N_ = result.load_N;
  solved_any_ = result.solved[0] || result.solved[1];
  for (int v = 0; v < 2; ++v) {
    EndplateSurface& s = surfaces_[v];
    s.endplate_peak_Pa = result.peak_Pa[static_cast<int>(endplate_measure(v))];
    for (std::size_t k = 0; k < s.stress_Pa.size(); ++k)
      s.stress_Pa[k] =
          result.solved[v] ? scratch_.solution[v].element_von_mises_Pa[face_tets_[v][k]] : 0.0;
  }
}

void draw_bone_stress_pane(BoneStressPane& pane, double* t_s) {
  pane.show_time(*t_s);
  ImGui::TextUnformatted("Bone stress at the disc");
  char label[96];
  std::snprintf(label, sizeof label, "Peak bone load (%.2f N at %.2f s)", pane.peak_load_N(),
                pane.peak_load_t_s());
  if (ImGui::SmallButton(label)) {
    *t_s = pane.peak_load_t_s();
    pane.show_time(*t_s);
  }
  ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.62f, 0.64f, 0.68f, 1.0f));
  text_wrapped("sample at %.2f s, %.2f N on the bone%s. C4's lower endplate from below, "
                     "C5's upper from above, anterior up; endplate peaks %.3g and %.3g MPa.",
                     pane.sample_t_s(), pane.sample_load_N(),
                     pane.sample_solved() ? "" : " (too little to solve: no stress)",
                     pane.surface(0).endplate_peak_Pa * 1e-6,
                     pane.surface(1).endplate_peak_Pa * 1e-6);
  ImGui::PopStyleColor();

  // Both views at one scale: x across, anterior (+z in the segment frame) up.
  Eigen::AlignedBox2d box;
  for (int v = 0; v < 2; ++v)
    for (const auto& tri : pane.surface(v).triangles)
      for (const Vec3& p : tri) box.extend(Eigen::Vector2d(p.x(), p.z()));
  if (box.isEmpty()) return;
  const float legend_w = 86.0f, gap = 8.0f;
  const float panel_w = std::max(
      80.0f, (ImGui::GetContentRegionAvail().x - legend_w - 2.0f * gap) * 0.5f);
  // As tall as the pane has room for, up to a little less than square.
  const float panel_h = std::clamp(ImGui::GetContentRegionAvail().y - 4.0f, 60.0f,
                                   std::min(190.0f, panel_w * 0.85f));
  const double scale =
      std::min((panel_w - 12.0) / box.sizes().x(), (panel_h - 44.0) / box.sizes().y());
  const double top = pane.scale_top_Pa();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  for (int v = 0; v < 2; ++v) {
    if (v == 1) ImGui::SameLine(0, gap);
    const EndplateSurface& s = pane.surface(v);
    const ImVec2 a = ImGui::GetCursorScreenPos();
    const ImVec2 b(a.x + panel_w, a.y + panel_h);
    ImGui::Dummy(ImVec2(panel_w, panel_h));
    dl->AddRectFilled(a, b, IM_COL32(22, 24, 28, 255));
    dl->PushClipRect(a, b, true);
    const ImVec2 centre((a.x + b.x) * 0.5f, (a.y + b.y) * 0.5f);
    const Eigen::Vector2d mid = box.center();
    // Seen from below, C4's left and right swap.
    const double mirror = v == 0 ? -1.0 : 1.0;
    auto project = [&](const Vec3& p) {
      return ImVec2(centre.x + static_cast<float>(mirror * (p.x() - mid.x()) * scale),
                    centre.y - static_cast<float>((p.z() - mid.y()) * scale));
    };
    for (std::size_t k = 0; k < s.triangles.size(); ++k) {
      const auto& tri = s.triangles[k];
      const Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
      const float shade = 0.55f + 0.45f * static_cast<float>(std::abs(n.y()));
      const Eigen::Vector4f c = stress_color(s.stress_Pa[k] / top);
      dl->AddTriangleFilled(project(tri[0]), project(tri[1]), project(tri[2]),
                            ImGui::ColorConvertFloat4ToU32(
                                ImVec4(c[0] * shade, c[1] * shade, c[2] * shade, 1.0f)));
    }
    dl->AddText(ImVec2(a.x + 5, a.y + 3), IM_COL32(225, 225, 230, 255), v == 0 ? "C4" : "C5");
    dl->PopClipRect();
    dl->AddRect(a, b, IM_COL32(90, 92, 98, 255));
  }
  // The legend: the bands of the scale, 0 at the bottom, in MPa.
  ImGui::SameLine(0, gap);
  const ImVec2 a = ImGui::GetCursorScreenPos();
  ImGui::Dummy(ImVec2(legend_w, panel_h));
  const float bar_w = 16.0f, bar_top = a.y + 22.0f, bar_h = panel_h - 32.0f;
  dl->AddText(ImVec2(a.x, a.y + 2), IM_COL32(225, 225, 230, 255), "MPa");
  constexpr int kBands = 12;
  for (int i = 0; i < kBands; ++i) {
    const Eigen::Vector4f c = stress_color((i + 0.5) / kBands);
    const float y1 = bar_top + bar_h * (1.0f - static_cast<float>(i) / kBands);
    const float y0 = bar_top + bar_h * (1.0f - static_cast<float>(i + 1) / kBands);
    dl->AddRectFilled(ImVec2(a.x, y0), ImVec2(a.x + bar_w, y1),
                      ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], 1.0f)));
  }
  for (int k = 0; k <= 4; ++k) {
    const float y = bar_top + bar_h * (1.0f - k / 4.0f);
    char tick[32];
    std::snprintf(tick, sizeof tick, k == 4 ? ">=%.3g" : "%.3g", top * 1e-6 * k / 4.0);
    dl->AddLine(ImVec2(a.x + bar_w, y), ImVec2(a.x + bar_w + 4, y), IM_COL32(220, 220, 225, 255));
    dl->AddText(ImVec2(a.x + bar_w + 6, y - 7), IM_COL32(220, 220, 225, 255), tick);
  }
}

}  // namespace acdr

// The trainee view's bone stress view: see live_bone_stress.hpp.
#include "ui/live_bone_stress.hpp"

#include <algorithm>
#include <cstdio>

#include "ui/bone_stress_pane.hpp"
#include "ui/bone_stress_view.hpp"

namespace acdr {

void LiveBoneStress::update(BoneStressWorker& worker) {
  const BoneSegment* bone = worker.bone();
  if (!bone) return;
  const bool fresh = worker.latest_field().read([&](const BoneStressField& f) { field_ = f; },
                                                &seen_);
  if (!fresh) return;
  ++shown_;
  peak_Pa_ = 0.0;
  for (const auto& vm : field_.element_von_mises_Pa)
    for (float s : vm) peak_Pa_ = std::max(peak_Pa_, static_cast<double>(s));
  top_Pa_ = std::max(top_Pa_, nice_stress_top(std::max(peak_Pa_, 0.05e6)));
  meshes_.clear();
  for (int v = 0; v < 2; ++v) {
    const BoneFem& fem = bone->vertebra(v);
    const auto& vm = field_.element_von_mises_Pa[v];
    std::vector<RenderMesh> bands(kBands);
    for (int b = 0; b < kBands; ++b) {
      bands[b].rgba = stress_color((b + 0.5) / kBands);
      bands[b].specular = 0.12f;
      // Fixed until the next field: uploaded once (ids unique per field, vertebra and band).
      bands[b].geometry_id = (0xB0DEull << 48) | (shown_ << 8) | static_cast<std::uint64_t>(v * kBands + b);
    }
    for (const BoundaryFace& f : fem.surface().faces()) {
      const double s = vm.empty() ? 0.0 : vm[f.tet];
      const int b = std::clamp(static_cast<int>(s / top_Pa_ * kBands), 0, kBands - 1);
      RenderMesh& m = bands[b];
      for (std::uint32_t n : f.nodes) {
        m.indices.push_back(static_cast<std::uint32_t>(m.vertices.size()));
        m.vertices.push_back(fem.mesh().nodes[n].cast<float>());
      }
    }
    for (RenderMesh& m : bands)
      if (!m.indices.empty()) meshes_.push_back(std::move(m));
  }
}

void LiveBoneStress::apply(RenderScene& scene, std::span<const std::uint64_t> bone_ids) const {
  if (!has_field()) return;
  std::erase_if(scene.meshes, [&](const RenderMesh& m) {
    return std::find(bone_ids.begin(), bone_ids.end(), m.geometry_id) != bone_ids.end();
  });
  scene.meshes.insert(scene.meshes.end(), meshes_.begin(), meshes_.end());
}

void LiveBoneStress::draw_legend(const ImVec2& display, float top) const {
  const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                                 ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing;
  ImGui::SetNextWindowPos(ImVec2(display.x - 12.0f, top + 12.0f), ImGuiCond_Always, ImVec2(1.0f, 0.0f));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("Bone stress legend", nullptr, fixed);
  ImGui::TextUnformatted("Bone stress (B)");
  if (!has_field()) {
    ImGui::TextUnformatted("waiting for the solver");
    ImGui::End();
    return;
  }
  ImGui::Text("von Mises, MPa");
  const float bar_h = 120.0f, bar_w = 18.0f;  // short enough to sit between the status window and the depth gauge
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  for (int b = 0; b < kBands; ++b) {
    const Eigen::Vector4f c = stress_color((b + 0.5) / kBands);
    const float y1 = p0.y + bar_h * (1.0f - static_cast<float>(b) / kBands);
    const float y0 = p0.y + bar_h * (1.0f - static_cast<float>(b + 1) / kBands);
    dl->AddRectFilled(ImVec2(p0.x, y0), ImVec2(p0.x + bar_w, y1),
                      ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], 1.0f)));
  }
  for (int t = 0; t <= 4; ++t) {
    const float y = p0.y + bar_h * (1.0f - t / 4.0f);
    char label[32];
    std::snprintf(label, sizeof label, "%.3g", top_Pa_ * 1e-6 * t / 4.0);
    dl->AddLine(ImVec2(p0.x + bar_w, y), ImVec2(p0.x + bar_w + 4.0f, y), IM_COL32(230, 230, 230, 255));
    dl->AddText(ImVec2(p0.x + bar_w + 7.0f, y - 7.0f), IM_COL32(230, 230, 230, 255), label);
  }
  ImGui::Dummy(ImVec2(bar_w + 60.0f, bar_h + 4.0f));
  ImGui::Text("at %.2f s, peak %.3g MPa", field_.result.t_s, peak_Pa_ * 1e-6);
  ImGui::Text("load on bone %.2f N", field_.result.load_N);
  ImGui::End();
}

}  // namespace acdr

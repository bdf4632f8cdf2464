// A check that every piece of text a view laid out this ImGui frame fits where it is drawn:
// called at the end of a frame's drawing (inside an ImGuiOffscreen draw function, after the
// views), it lists what was clipped. Three kinds:
//  - a window whose laid-out items (each text item is as wide as ImGui::CalcTextSize says) reach
//    past its inner width, or below its bottom without a scrollbar to get there;
//  - a table column whose cells or header need more width than the column has (a table
//    nested in a column must fit the column, and is checked column by column itself);
//  - a window that lies partly outside the display;
//  - a glyph drawn straight to a draw list (plot labels, legends) that lies partly outside its
//    clip rectangle or the display (except a line half scrolled out of a pane that scrolls).
// Empty: nothing is cut off.
// hidden_panes below checks, for named panes (child windows), that each was drawn and shows
// whole: on the display and inside what its parents show (not below the fold of a scrolled
// pane).
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include <imgui.h>
#include <imgui_internal.h>

namespace acdr::test {

inline std::vector<std::string> text_overflows(const ImVec2& display, float tolerance = 1.0f) {
  std::vector<std::string> out;
  ImGuiContext& g = *GImGui;
  auto px = [](float v) { return std::to_string(static_cast<int>(v + 0.5f)); };
  for (ImGuiWindow* w : g.Windows) {
    if (!w->WasActive && !w->Active) continue;
    if (w->Hidden || w->LastFrameActive != g.FrameCount) continue;
    const std::string name = w->Name;
    if (name.rfind("Debug##", 0) == 0) continue;  // ImGui's implicit window
    const ImRect r = w->Rect();
    if (!(w->Flags & ImGuiWindowFlags_ChildWindow) &&
        (r.Min.x < -tolerance || r.Min.y < -tolerance || r.Max.x > display.x + tolerance ||
         r.Max.y > display.y + tolerance))
      out.push_back("window '" + name + "' reaches outside the display: " + px(r.Min.x) + "," +
                    px(r.Min.y) + " to " + px(r.Max.x) + "," + px(r.Max.y));
    const ImVec2 content = w->DC.CursorMaxPos;
    if (!w->ScrollbarX && content.x > w->InnerClipRect.Max.x + tolerance)
      out.push_back("window '" + name + "': text needs " +
                    px(content.x - w->InnerClipRect.Min.x) + " px, has " +
                    px(w->InnerClipRect.GetWidth()));
    if (!w->ScrollbarY && !(w->Flags & ImGuiWindowFlags_AlwaysAutoResize) &&
        content.y > w->InnerClipRect.Max.y + tolerance + g.Style.ItemSpacing.y)
      out.push_back("window '" + name + "': content " + px(content.y - w->InnerClipRect.Min.y) +
                    " px high in " + px(w->InnerClipRect.GetHeight()) + ", no scrollbar");
  }
  std::vector<ImGuiTable*> tables;
  for (int i = 0; i < g.Tables.GetMapSize(); ++i)
    if (ImGuiTable* t = g.Tables.TryGetMapData(i); t && t->LastFrameActive == g.FrameCount)
      tables.push_back(t);
  for (ImGuiTable* t : tables) {
    const std::string table = t->OuterWindow ? std::string(t->OuterWindow->Name) : "?";
    for (int c = 0; c < t->ColumnsCount; ++c) {
      const ImGuiTableColumn& col = t->Columns[c];
      if (!col.IsVisibleX) continue;
      // A table nested in this column reports its ideal width (every cell unwrapped) as the
      // column's content; its own columns are checked instead, and its outer edge here.
      bool nested = false;
      for (ImGuiTable* u : tables) {
        if (u == t || u->OuterRect.Min.x < col.MinX - tolerance || u->OuterRect.Min.x >= col.MaxX ||
            u->OuterRect.Min.y < t->OuterRect.Min.y || u->OuterRect.Min.y > t->OuterRect.Max.y)
          continue;
        nested = true;
        if (u->OuterRect.Max.x > col.MaxX + tolerance)
          out.push_back("table in '" + table + "', column " + std::to_string(c) +
                        ": a table in it is " + px(u->OuterRect.GetWidth()) + " px wide, has " +
                        px(col.MaxX - u->OuterRect.Min.x));
      }
      const float content = std::max(col.ContentMaxXUnfrozen, col.ContentMaxXFrozen);
      if (!nested && content > col.WorkMaxX + tolerance)
        out.push_back("table in '" + table + "', column " + std::to_string(c) + ": a cell needs " +
                      px(content - col.WorkMinX) + " px, has " + px(col.WorkMaxX - col.WorkMinX));
      if (col.ContentMaxXHeadersIdeal > col.WorkMaxX + tolerance)
        out.push_back("table in '" + table + "', column " + std::to_string(c) +
                      ": the header needs " + px(col.ContentMaxXHeadersIdeal - col.WorkMinX) +
                      " px, has " + px(col.WorkMaxX - col.WorkMinX));
    }
  }
  // Glyphs (vertices not on the font atlas's white pixel) against their clip rectangles.
  const ImVec2 white = g.DrawListSharedData.TexUvWhitePixel;
  // Anti-aliased lines take their UVs from baked line textures in the atlas: not glyphs.
  ImRect line_uvs(ImVec2(1, 1), ImVec2(0, 0));
  for (const ImVec4& uv : g.IO.Fonts->TexUvLines) {
    const ImRect r(ImVec2(uv.x, uv.y), ImVec2(uv.z, uv.w));
    if (line_uvs.Min.x > line_uvs.Max.x)
      line_uvs = r;
    else
      line_uvs.Add(r);
  }
  auto is_glyph_uv = [&](const ImVec2& uv) {
    if (uv.x == white.x && uv.y == white.y) return false;
    return !(uv.x >= line_uvs.Min.x && uv.x <= line_uvs.Max.x && uv.y >= line_uvs.Min.y &&
             uv.y <= line_uvs.Max.y);
  };
  for (ImGuiWindow* w : g.Windows) {
    if (w->Hidden || w->LastFrameActive != g.FrameCount) continue;
    const ImDrawList* dl = w->DrawList;
    for (const ImDrawCmd& cmd : dl->CmdBuffer) {
      const ImVec4 clip = cmd.ClipRect;
      // Triangle by triangle: a glyph partly inside its clip rectangle and partly outside is
      // cut (one wholly outside is scrolled away or not drawn, and is not a cut).
      for (unsigned k = cmd.IdxOffset; k + 2 < cmd.IdxOffset + cmd.ElemCount; k += 3) {
        ImRect box;
        bool glyph = false;
        for (unsigned j = 0; j < 3; ++j) {
          const ImDrawVert& v = dl->VtxBuffer[dl->IdxBuffer[k + j] + cmd.VtxOffset];
          glyph = glyph || is_glyph_uv(v.uv);
          if (j == 0)
            box = ImRect(v.pos, v.pos);
          else
            box.Add(v.pos);
        }
        if (!glyph) continue;
        const ImRect area(ImMax(ImVec2(clip.x, clip.y), ImVec2(0, 0)),
                          ImMin(ImVec2(clip.z, clip.w), display));
        const bool inside = box.Min.x >= area.Min.x - tolerance &&
                            box.Max.x <= area.Max.x + tolerance &&
                            box.Min.y >= area.Min.y - tolerance &&
                            box.Max.y <= area.Max.y + tolerance;
        if (inside || !box.Overlaps(area)) continue;
        // A line half scrolled out of a pane with a vertical scrollbar is not cut: the
        // scrollbar brings it in.
        if (w->ScrollbarY && box.Min.x >= area.Min.x - tolerance &&
            box.Max.x <= area.Max.x + tolerance)
          continue;
        out.push_back("window '" + std::string(w->Name) + "': a glyph at " + px(box.Min.x) + "," +
                      px(box.Min.y) + " is cut at its clip rectangle " + px(area.Min.x) + "," +
                      px(area.Min.y) + " to " + px(area.Max.x) + "," + px(area.Max.y));
        break;
      }
    }
  }
  return out;
}

/// Each pane named (the name given to ImGui::BeginChild) drawn this frame and wholly visible:
/// inside the display and inside the visible inner area of every window that holds it. Lists
/// what is not: a pane missing, or where it reaches past the display or a parent's edge.
inline std::vector<std::string> hidden_panes(const ImVec2& display,
                                             std::initializer_list<const char*> names,
                                             float tolerance = 1.0f) {
  std::vector<std::string> out;
  ImGuiContext& g = *GImGui;
  auto px = [](float v) { return std::to_string(static_cast<int>(v + 0.5f)); };
  auto inside = [&](const ImRect& r, const ImRect& area) {
    return r.Min.x >= area.Min.x - tolerance && r.Min.y >= area.Min.y - tolerance &&
           r.Max.x <= area.Max.x + tolerance && r.Max.y <= area.Max.y + tolerance;
  };
  for (const char* name : names) {
    // A child window is named "<parent>/<name>_<id in hex>".
    const std::string key = "/" + std::string(name) + "_";
    ImGuiWindow* pane = nullptr;
    for (ImGuiWindow* w : g.Windows)
      if ((w->Flags & ImGuiWindowFlags_ChildWindow) && w->LastFrameActive == g.FrameCount &&
          !w->Hidden && std::string(w->Name).find(key) != std::string::npos)
        pane = w;
    if (!pane) {
      out.push_back("pane '" + std::string(name) + "' is not drawn");
      continue;
    }
    const ImRect r = pane->Rect();
    const std::string where = px(r.Min.x) + "," + px(r.Min.y) + " to " + px(r.Max.x) + "," +
                              px(r.Max.y);
    if (!inside(r, ImRect(ImVec2(0, 0), display)))
      out.push_back("pane '" + std::string(name) + "' at " + where + " reaches outside the display");
    for (ImGuiWindow* p = pane->ParentWindow; p; p = p->ParentWindow)
      if (!inside(r, p->InnerClipRect))
        out.push_back("pane '" + std::string(name) + "' at " + where + " is not all shown by '" +
                      p->Name + "' (" + px(p->InnerClipRect.Min.y) + " to " +
                      px(p->InnerClipRect.Max.y) + " high)");
  }
  return out;
}

}  // namespace acdr::test

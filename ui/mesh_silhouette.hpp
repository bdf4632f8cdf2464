// The outline a closed mesh casts on an axis plane, as filled cells: the dashboard's replay
// draws the vertebrae this way (a few hundred rectangles instead of 10^5 triangles a frame).
#pragma once

#include <vector>

#include "engine/core/types.hpp"
#include "engine/geometry/triangle_mesh.hpp"

namespace acdr {

/// Cells of a square grid on the plane of axes (`ax`, `ay`) covered by a mesh's projection,
/// stored as runs along `ax`: cell (i, j) spans [origin + (i, j) * cell, + cell].
struct MeshSilhouette {
  int ax = 0, ay = 1;
  double cell_m = 0.0;
  double origin_a = 0.0, origin_b = 0.0;  ///< the grid's corner on axes ax, ay (m)
  struct Run {
    int row = 0;            ///< j
    int first = 0, last = 0;  ///< i, inclusive
  };
  std::vector<Run> runs;

  bool empty() const { return runs.empty(); }
};

/// The silhouette of `meshes` projected along the third axis onto (`ax`, `ay`), with cells of
/// `cell_m` (a cell is covered when its centre lies in a projected triangle).
MeshSilhouette project_silhouette(const std::vector<const TriangleMesh*>& meshes, int ax, int ay,
                                  double cell_m);

}  // namespace acdr

// A box cut into cubes, each cube into six tetrahedra around its main diagonal (the Kuhn
// split, conforming between neighbouring cubes): the structured meshes of the analytic
// verification cases (uniform compression, the cantilever) and of the tests.
#pragma once

#include <array>

#include "engine/bone/tet_mesh.hpp"

namespace acdr {

/// Box [lo, hi] with cells[k] divisions along axis k: (n0+1)(n1+1)(n2+1) nodes, numbered x
/// fastest, and 6 n0 n1 n2 positively oriented tetrahedra, all region 0.
TetMesh make_box_tet_mesh(const Vec3& lo_m, const Vec3& hi_m, const std::array<int, 3>& cells);

}  // namespace acdr

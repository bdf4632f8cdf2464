// Simple closed triangle meshes with known geometry: an axis-aligned box and a subdivided
// icosahedron (sphere). Used as test subjects for mesh checks, file round trips and signed
// distance grids, and as placeholders an author can export.
#pragma once

#include "engine/geometry/triangle_mesh.hpp"

namespace acdr {

/// Closed box, 8 vertices and 12 outward triangles.
TriangleMesh make_box_mesh(const Vec3& min_m, const Vec3& max_m);

/// Sphere approximated by an icosahedron subdivided `subdivisions` times (20 * 4^s triangles),
/// vertices on the sphere.
TriangleMesh make_sphere_mesh(const Vec3& center_m, double radius_m, int subdivisions);

}  // namespace acdr

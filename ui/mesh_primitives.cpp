// Tessellation of the primitive shapes. Triangles are added through one helper that orients
// each triangle by the normals of its vertices, so no builder can get a winding wrong.
#include "ui/mesh_primitives.hpp"

#include <algorithm>
#include <cmath>

namespace acdr {

namespace {
constexpr float kPi = 3.14159265358979f;

std::uint32_t add_vertex(RenderMesh& mesh, const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  mesh.vertices.push_back(p);
  mesh.normals.push_back(n.normalized());
  return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
}

// Adds triangle (i, j, k), swapping two corners when its geometric normal points against the
// vertices' outward normals. Degenerate triangles (at a sphere's pole) are dropped.
void add_triangle(RenderMesh& mesh, std::uint32_t i, std::uint32_t j, std::uint32_t k) {
  const Eigen::Vector3f& a = mesh.vertices[i];
  const Eigen::Vector3f face = (mesh.vertices[j] - a).cross(mesh.vertices[k] - a);
  if (face.squaredNorm() <= 1e-30f) return;
  const Eigen::Vector3f outward = mesh.normals[i] + mesh.normals[j] + mesh.normals[k];
  if (face.dot(outward) < 0.0f) std::swap(j, k);
  mesh.indices.insert(mesh.indices.end(), {i, j, k});
}

void add_quad(RenderMesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c,
              std::uint32_t d) {
  add_triangle(mesh, a, b, c);
  add_triangle(mesh, a, c, d);
}

// An orthonormal frame (u, v, w) with w along `axis`.
struct Frame {
  Eigen::Vector3f u, v, w;
};
Frame frame_along(const Eigen::Vector3f& axis) {
  Frame f;
  f.w = axis.squaredNorm() > 0.0f ? axis.normalized() : Eigen::Vector3f(0, 0, 1);
  f.u = f.w.unitOrthogonal();
  f.v = f.w.cross(f.u);
  return f;
}

// A band of a sphere around `center` in `frame`, polar angle theta (from +w) from theta0 to
// theta1, `rings` rings and `segments` around. `inward` turns the normals towards the centre
// (the inside of a hollow). Vertices are duplicated at the seam so normals stay smooth.
void add_sphere_band(RenderMesh& mesh, const Eigen::Vector3f& center, float radius,
                     const Frame& frame, float theta0, float theta1, int rings, int segments,
                     bool inward) {
  const std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int r = 0; r <= rings; ++r) {
    const float theta = theta0 + (theta1 - theta0) * static_cast<float>(r) / rings;
    for (int s = 0; s <= segments; ++s) {
      const float phi = 2.0f * kPi * static_cast<float>(s) / segments;
      const Eigen::Vector3f dir = std::sin(theta) * (std::cos(phi) * frame.u +
                                                     std::sin(phi) * frame.v) +
                                  std::cos(theta) * frame.w;
      add_vertex(mesh, center + radius * dir, inward ? -dir : dir);
    }
  }
  const std::uint32_t row = static_cast<std::uint32_t>(segments + 1);
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t a = first + r * row + s;
      add_quad(mesh, a, a + 1, a + row + 1, a + row);
    }
  }
}

// The side of a cylinder from a to b (smooth normals, seam duplicated).
void add_cylinder_side(RenderMesh& mesh, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                       float radius, const Frame& frame, int segments) {
  const std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int s = 0; s <= segments; ++s) {
    const float phi = 2.0f * kPi * static_cast<float>(s) / segments;
    const Eigen::Vector3f radial = std::cos(phi) * frame.u + std::sin(phi) * frame.v;
    add_vertex(mesh, a + radius * radial, radial);
    add_vertex(mesh, b + radius * radial, radial);
  }
  for (int s = 0; s < segments; ++s) {
    const std::uint32_t i = first + 2 * s;
    add_quad(mesh, i, i + 2, i + 3, i + 1);
  }
}

// A flat disc (or ring, when inner > 0) at `center` facing `normal`.
void add_ring(RenderMesh& mesh, const Eigen::Vector3f& center, const Eigen::Vector3f& normal,
              float inner, float outer, const Frame& frame, int segments) {
  const std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int s = 0; s <= segments; ++s) {
    const float phi = 2.0f * kPi * static_cast<float>(s) / segments;
    const Eigen::Vector3f radial = std::cos(phi) * frame.u + std::sin(phi) * frame.v;
    add_vertex(mesh, center + inner * radial, normal);
    add_vertex(mesh, center + outer * radial, normal);
  }
  for (int s = 0; s < segments; ++s) {
    const std::uint32_t i = first + 2 * s;
    add_quad(mesh, i, i + 2, i + 3, i + 1);
  }
}

void add_box_faces(RenderMesh& mesh, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  // Four vertices per face so each face keeps its own flat normal.
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = side ? 1.0f : -1.0f;
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      std::uint32_t corner[4];
      for (int c = 0; c < 4; ++c) {
        Eigen::Vector3f p;
        p[axis] = side ? hi[axis] : lo[axis];
        p[u] = (c == 1 || c == 2) ? hi[u] : lo[u];
        p[v] = (c >= 2) ? hi[v] : lo[v];
        corner[c] = add_vertex(mesh, p, n);
      }
      add_quad(mesh, corner[0], corner[1], corner[2], corner[3]);
    }
  }
}
}  // namespace

RenderMesh make_box(const Eigen::Vector3f& min, const Eigen::Vector3f& max,
                    const Eigen::Vector4f& rgba) {
  RenderMesh mesh;
  mesh.rgba = rgba;
  add_box_faces(mesh, min.cwiseMin(max), min.cwiseMax(max));
  return mesh;
}

RenderMesh make_oriented_box(const Eigen::Vector3f& half_extents_m, const Eigen::Affine3f& pose,
                             const Eigen::Vector4f& rgba) {
  RenderMesh mesh;
  mesh.rgba = rgba;
  const Eigen::Vector3f h = half_extents_m.cwiseAbs();
  add_box_faces(mesh, -h, h);
  mesh.pose = pose;
  return mesh;
}

RenderMesh make_rounded_box(const Eigen::Vector3f& half_extents_m, float rounding_m,
                            const Eigen::Affine3f& pose, const Eigen::Vector4f& rgba, int segments) {
  const Eigen::Vector3f h = half_extents_m.cwiseAbs();
  const float r = std::clamp(rounding_m, 0.0f, h.minCoeff());
  if (r <= 0.0f) return make_oriented_box(h, pose, rgba);
  // A sphere of the rounding's radius with each octant moved out to its corner of the inner
  // box: the triangles that straddle an axis plane stretch into the flat faces, and every
  // vertex keeps its sphere normal, which is the rounded box's normal there.
  RenderMesh mesh = make_sphere(Eigen::Vector3f::Zero(), r, rgba, segments);
  const Eigen::Vector3f core = h - Eigen::Vector3f::Constant(r);
  for (Eigen::Vector3f& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) v[k] += v[k] > 0.0f ? core[k] : v[k] < 0.0f ? -core[k] : 0.0f;
  }
  mesh.pose = pose;
  return mesh;
}

RenderMesh make_cylinder(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float radius_m,
                         const Eigen::Vector4f& rgba, int segments, bool capped) {
  RenderMesh mesh;
  mesh.rgba = rgba;
  segments = std::max(segments, 3);
  const Frame frame = frame_along(b - a);
  add_cylinder_side(mesh, a, b, radius_m, frame, segments);
  if (capped) {
    add_ring(mesh, a, -frame.w, 0.0f, radius_m, frame, segments);
    add_ring(mesh, b, frame.w, 0.0f, radius_m, frame, segments);
  }
  return mesh;
}

RenderMesh make_capsule(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float radius_m,
                        const Eigen::Vector4f& rgba, int segments) {
  RenderMesh mesh;
  mesh.rgba = rgba;
  segments = std::max(segments, 4);
  const Frame frame = frame_along(b - a);
  const int rings = std::max(segments / 4, 2);
  add_cylinder_side(mesh, a, b, radius_m, frame, segments);
  add_sphere_band(mesh, b, radius_m, frame, 0.0f, 0.5f * kPi, rings, segments, false);
  add_sphere_band(mesh, a, radius_m, frame, 0.5f * kPi, kPi, rings, segments, false);
  return mesh;
}

RenderMesh make_sphere(const Eigen::Vector3f& center, float radius_m, const Eigen::Vector4f& rgba,
                       int segments) {
  RenderMesh mesh;
  mesh.rgba = rgba;
  segments = std::max(segments, 4);
  add_sphere_band(mesh, center, radius_m, frame_along(Eigen::Vector3f(0, 0, 1)), 0.0f, kPi,
                  segments / 2, segments, false);
  return mesh;
}

RenderMesh make_cup_shell(const Eigen::Vector3f& center, const Eigen::Vector3f& opening,
                          float inner_radius_m, float wall_m, const Eigen::Vector4f& rgba,
                          int segments) {
  RenderMesh mesh;
  mesh.rgba = rgba;
  segments = std::max(segments, 4);
  const Frame frame = frame_along(opening);
  const int rings = std::max(segments / 4, 2);
  const float outer = inner_radius_m + std::max(wall_m, 0.0f);
  // The bowl is the half of the sphere on the -opening side: polar angles pi/2..pi from +w.
  add_sphere_band(mesh, center, outer, frame, 0.5f * kPi, kPi, rings, segments, false);
  add_sphere_band(mesh, center, inner_radius_m, frame, 0.5f * kPi, kPi, rings, segments, true);
  add_ring(mesh, center, frame.w, inner_radius_m, outer, frame, segments);
  return mesh;
}

void append_mesh(RenderMesh& mesh, const RenderMesh& part) {
  const std::uint32_t offset = static_cast<std::uint32_t>(mesh.vertices.size());
  // Normals are either complete for both meshes or dropped (the renderer then computes them).
  const bool keep_normals = mesh.normals.size() == mesh.vertices.size() &&
                            part.normals.size() == part.vertices.size();
  mesh.vertices.insert(mesh.vertices.end(), part.vertices.begin(), part.vertices.end());
  if (keep_normals) {
    mesh.normals.insert(mesh.normals.end(), part.normals.begin(), part.normals.end());
  } else {
    mesh.normals.clear();
  }
  for (std::uint32_t index : part.indices) mesh.indices.push_back(index + offset);
}

}  // namespace acdr

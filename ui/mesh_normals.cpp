// Crease-aware vertex normals.
#include "ui/mesh_normals.hpp"

#include <cmath>

namespace acdr {

NormalMesh compute_crease_normals(const std::vector<Eigen::Vector3f>& vertices,
                                  const std::vector<std::uint32_t>& indices,
                                  float crease_angle_deg, int* dropped) {
  NormalMesh out;
  const std::size_t vertex_count = vertices.size();

  // Keep the valid triangles and their area-weighted face normals (the cross product's length
  // is twice the area, which is the weight).
  std::vector<std::uint32_t> tris;
  std::vector<Eigen::Vector3f> face_normal;
  int bad = 0;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const std::uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
    if (a >= vertex_count || b >= vertex_count || c >= vertex_count) {
      ++bad;
      continue;
    }
    const Eigen::Vector3f n = (vertices[b] - vertices[a]).cross(vertices[c] - vertices[a]);
    if (!(n.squaredNorm() > 0.0f) || !n.allFinite()) {
      ++bad;
      continue;
    }
    tris.insert(tris.end(), {a, b, c});
    face_normal.push_back(n);
  }
  if (dropped) *dropped = bad;
  const std::size_t face_count = face_normal.size();

  // Faces around each vertex, as compressed rows (offsets + list).
  std::vector<std::uint32_t> offset(vertex_count + 1, 0);
  for (std::uint32_t v : tris) ++offset[v + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) offset[v + 1] += offset[v];
  std::vector<std::uint32_t> incident(tris.size());
  std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
  for (std::size_t corner = 0; corner < tris.size(); ++corner) {
    incident[fill[tris[corner]]++] = static_cast<std::uint32_t>(corner / 3);
  }

  std::vector<Eigen::Vector3f> unit_face(face_count);
  for (std::size_t f = 0; f < face_count; ++f) unit_face[f] = face_normal[f].normalized();
  const float cos_crease = std::cos(crease_angle_deg * 3.14159265358979f / 180.0f);

  // For each corner, average the neighbouring faces on the same side of any crease; corners of
  // one vertex that end with (nearly) the same normal share an output vertex.
  std::vector<std::vector<std::uint32_t>> copies(vertex_count);  // output vertices per input
  out.indices.resize(tris.size());
  for (std::size_t corner = 0; corner < tris.size(); ++corner) {
    const std::uint32_t v = tris[corner];
    const std::size_t f = corner / 3;
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (std::uint32_t k = offset[v]; k < offset[v + 1]; ++k) {
      const std::uint32_t g = incident[k];
      if (unit_face[g].dot(unit_face[f]) >= cos_crease) sum += face_normal[g];
    }
    const Eigen::Vector3f n = sum.squaredNorm() > 0.0f ? sum.normalized() : unit_face[f];
    std::uint32_t index = UINT32_MAX;
    for (std::uint32_t candidate : copies[v]) {
      if (out.normals[candidate].dot(n) > 0.9999f) {
        index = candidate;
        break;
      }
    }
    if (index == UINT32_MAX) {
      index = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(vertices[v]);
      out.normals.push_back(n);
      copies[v].push_back(index);
    }
    out.indices[corner] = index;
  }
  return out;
}

}  // namespace acdr

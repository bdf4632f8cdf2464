// CGAL Mesh_3 behind a plain interface: only this file includes CGAL (its templates are heavy
// to compile). The surface is scaled to millimetres for meshing so the criteria and the
// optimisers work with numbers near 1; the result is scaled back to metres.
#include "engine/bone/tet_mesher.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polyhedral_mesh_domain_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/make_mesh_3.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <vector>

namespace acdr {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;
using Domain = CGAL::Polyhedral_mesh_domain_3<Surface, Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

constexpr double kMmPerM = 1e3;

Surface to_cgal(const TriangleMesh& mesh) {
  Surface s;
  std::vector<Surface::Vertex_index> v;
  v.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices)
    v.push_back(s.add_vertex(Point(p.x() * kMmPerM, p.y() * kMmPerM, p.z() * kMmPerM)));
  for (const auto& t : mesh.triangles) s.add_face(v[t[0]], v[t[1]], v[t[2]]);
  return s;
}

// Self-intersection is the one defect check_closed_mesh cannot see.
std::string self_intersection_error(const Surface& s) {
  std::vector<std::pair<Surface::Face_index, Surface::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(s, std::back_inserter(pairs));
  if (pairs.empty()) return "";
  const auto h = s.halfedge(pairs.front().first);
  const Point& p = s.point(s.target(h));
  char text[200];
  std::snprintf(text, sizeof text,
                "the surface intersects itself (%zu pairs of triangles), first near "
                "(%.2f, %.2f, %.2f mm)",
                pairs.size(), p.x(), p.y(), p.z());
  return text;
}

}  // namespace


TetMeshingResult mesh_closed_surface(const TriangleMesh& surface, const TetMeshingParams& params) {
  const auto start = std::chrono::steady_clock::now();
  TetMeshingResult result;
  auto finish = [&](std::string error) {
    result.error = std::move(error);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };
  if (std::string bad = validate_tet_meshing_params(params); !bad.empty()) {
    bad.pop_back();
    return finish("bad meshing parameters: " + bad);
  }
  // The surface first: holes, non-manifold or flipped edges, degenerate triangles, then
  // self-intersections. Each would make the inside/outside test of the domain meaningless.
  const MeshCheck check = check_closed_mesh(surface);
  if (!check.ok) return finish("not a closed surface: " + check.error);
  if (!(check.volume_m3 > 0.0)) return finish("the surface encloses no volume");

  try {
    const Surface s = to_cgal(surface);
    if (std::string e = self_intersection_error(s); !e.empty()) return finish(e);

    // A fixed seed: the same surface and parameters give the same mesh.
    CGAL::Random random(0);
    Domain domain(s, &random);
    namespace P = CGAL::parameters;
    const double h = params.size_m * kMmPerM;
    const Criteria criteria(P::facet_angle = params.facet_angle_deg, P::facet_size = h,
                            P::facet_distance = params.surface_distance_ratio * h,
                            P::cell_radius_edge_ratio = params.radius_edge_ratio, P::cell_size = h);
    Complex c3t3 = CGAL::make_mesh_3<Complex>(domain, criteria, P::no_perturb(), P::no_exude());
    // No time limits: the result must not depend on the machine's speed.
    if (params.sliver_bound_deg > 0.0) {
      CGAL::perturb_mesh_3(c3t3, domain, P::time_limit = 0,
                           P::sliver_bound = params.sliver_bound_deg);
      CGAL::exude_mesh_3(c3t3, P::time_limit = 0, P::sliver_bound = params.sliver_bound_deg);
    }

    // Number the used vertices in the order the cells meet them (deterministic).
    TetMesh mesh;
    std::map<Triangulation::Vertex_handle, std::uint32_t> index;
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
      std::array<std::uint32_t, 4> tet{};
      for (int i = 0; i < 4; ++i) {
        const auto v = c->vertex(i);
        auto [it, added] = index.try_emplace(v, static_cast<std::uint32_t>(mesh.nodes.size()));
        if (added) {
          const auto& p = v->point().point();
          mesh.nodes.emplace_back(p.x() / kMmPerM, p.y() / kMmPerM, p.z() / kMmPerM);
        }
        tet[i] = it->second;
      }
      mesh.tets.push_back(tet);
      if (mesh.tet_volume(mesh.tets.size() - 1) < 0.0)
        std::swap(mesh.tets.back()[2], mesh.tets.back()[3]);
    }
    mesh.region.assign(mesh.tets.size(), 0);
    result.quality = tet_quality(mesh);
    if (mesh.tets.empty())
      return finish("the mesher produced no tetrahedra (surface too small for size_m?)");
    if (std::string bad = check_tet_quality(result.quality, params.limits); !bad.empty())
      return finish("mesh quality below the limits: " + bad);
    result.mesh = std::move(mesh);
    return finish("");
  } catch (const std::exception& e) {
    return finish(std::string("the mesher failed: ") + e.what());
  }
}

}  // namespace acdr

// Loads on the bone surface: a contact (an instrument tip, a particle of the nucleus) presses a
// force on the surface over a small patch. The pressure over the patch follows the Hertz
// profile p(r) ~ sqrt(1 - r^2 / a^2) around the surface point nearest the contact, and is turned
// into consistent nodal forces (the integral of the pressure times each node's shape function),
// so the nodal forces add up to the contact force exactly. A patch, not a point: the stress
// under a point load is infinite in the continuum and grows without bound as the mesh is
// refined, while a pressure of finite extent gives a stress field that converges.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "engine/bone/boundary_surface.hpp"
#include "engine/bone/elastic_model.hpp"

namespace acdr {

/// One contact on the bone (SI).
struct ContactLoad {
  Vec3 point_m = Vec3::Zero();  ///< contact point, on or near the surface
  Vec3 force_N = Vec3::Zero();  ///< force on the bone (a push into it points inward)
  /// Radius of the pressure patch (m). A curette tip is a few millimetres wide: 1 mm default.
  double radius_m = 1.0e-3;
};

/// Adds the contact's nodal forces to `force_N` (3 per node of `space`). The contact snaps to
/// the nearest surface point within `max_snap_m`; returns false (and adds nothing) when there is
/// none. A patch smaller than the faces falls back to the nearest face, shared by its shape
/// functions at the contact point. `scratch` is reused between calls (no allocation once warm).
bool add_contact_load(const FeSpace& space, const BoundarySurface& surface,
                      const ContactLoad& contact, double max_snap_m, std::span<double> force_N,
                      std::vector<std::uint32_t>& scratch);

/// Adds the consistent nodal forces of a uniform traction (Pa, force per area, on the bone) over
/// boundary face `face`: a third of traction times area to each corner for linear elements; for
/// quadratic ones a third to each edge node and none to the corners.
void add_face_traction(const FeSpace& space, const BoundarySurface& surface, std::size_t face,
                       const Vec3& traction_Pa, std::span<double> force_N);

}  // namespace acdr

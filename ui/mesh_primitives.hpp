// Builders of simple RenderMesh shapes (boxes, cylinders, capsules, spheres, a curette's cup):
// what scene converters, tests and previews use to turn configuration into geometry.
// Every builder stores outward unit normals and counter-clockwise triangles seen from outside.
// Lengths in metres.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ui/render_scene.hpp"

namespace acdr {

/// The default colour of a built mesh: light grey, opaque.
inline Eigen::Vector4f default_mesh_rgba() { return Eigen::Vector4f(0.8f, 0.8f, 0.8f, 1.0f); }

/// Axis-aligned box between two corners (world frame; pose identity). Flat faces.
RenderMesh make_box(const Eigen::Vector3f& min, const Eigen::Vector3f& max,
                    const Eigen::Vector4f& rgba = default_mesh_rgba());

/// Box of the given half extents centred on its local origin, placed by `pose` (stored in the
/// mesh's pose, so a moving body only updates the pose).
RenderMesh make_oriented_box(const Eigen::Vector3f& half_extents_m, const Eigen::Affine3f& pose,
                             const Eigen::Vector4f& rgba = default_mesh_rgba());

/// Box of the given half extents with its edges and corners rounded by `rounding_m` (at most
/// the smallest half extent; 0 gives make_oriented_box), placed by `pose`.
RenderMesh make_rounded_box(const Eigen::Vector3f& half_extents_m, float rounding_m,
                            const Eigen::Affine3f& pose,
                            const Eigen::Vector4f& rgba = default_mesh_rgba(), int segments = 32);

/// Cylinder of radius `radius_m` from point `a` to point `b` (world frame), with flat end
/// caps when `capped`. `segments` around (typically 24).
RenderMesh make_cylinder(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float radius_m,
                         const Eigen::Vector4f& rgba = default_mesh_rgba(), int segments = 24,
                         bool capped = true);

/// Capsule: a cylinder from `a` to `b` with hemispherical ends of the same radius.
RenderMesh make_capsule(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float radius_m,
                        const Eigen::Vector4f& rgba = default_mesh_rgba(), int segments = 24);

/// Sphere (latitude-longitude tessellation: `segments` around, segments/2 rings).
RenderMesh make_sphere(const Eigen::Vector3f& center, float radius_m,
                       const Eigen::Vector4f& rgba = default_mesh_rgba(), int segments = 32);

/// A curette's cup: a hemispherical shell of inner radius `inner_radius_m` and wall thickness
/// `wall_m`, whose rim lies in the plane through `center` perpendicular to `opening`, open
/// towards `opening` (the bowl bulges to -opening). Outer surface, inner surface (normals into
/// the hollow) and the flat rim ring.
RenderMesh make_cup_shell(const Eigen::Vector3f& center, const Eigen::Vector3f& opening,
                          float inner_radius_m, float wall_m,
                          const Eigen::Vector4f& rgba = default_mesh_rgba(), int segments = 32);

/// Appends `part` to `mesh` (both in the same frame; `part`'s pose is ignored). Lets callers
/// build one mesh from several primitives, e.g. a shaft and a blade.
void append_mesh(RenderMesh& mesh, const RenderMesh& part);

}  // namespace acdr

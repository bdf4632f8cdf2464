// The sample scene.
#include "ui/sample_scene.hpp"

#include <algorithm>
#include <cmath>

#include "ui/mesh_primitives.hpp"
#include "ui/render_camera.hpp"

namespace acdr {

RenderScene make_sample_scene(int particle_count, float aspect, const SampleSceneLayout& l,
                              const SampleSceneColors& colors) {
  RenderScene scene;

  // The seed's open box: a floor and four side walls around the cavity, open at +z.
  const Eigen::Vector3f& lo = l.inner_min;
  const Eigen::Vector3f& hi = l.inner_max;
  const float w = l.wall_m;
  const Eigen::Vector3f walls[5][2] = {
      {{lo.x() - w, lo.y() - w, lo.z() - w}, {hi.x() + w, hi.y() + w, lo.z()}},  // floor
      {{lo.x() - w, lo.y() - w, lo.z()}, {lo.x(), hi.y() + w, hi.z()}},          // -x
      {{hi.x(), lo.y() - w, lo.z()}, {hi.x() + w, hi.y() + w, hi.z()}},          // +x
      {{lo.x(), lo.y() - w, lo.z()}, {hi.x(), lo.y(), hi.z()}},                  // -y
      {{lo.x(), hi.y(), lo.z()}, {hi.x(), hi.y() + w, hi.z()}},                  // +y
  };
  for (int i = 0; i < 5; ++i) {
    scene.meshes.push_back(make_box(walls[i][0], walls[i][1], colors.walls));
    scene.meshes.back().geometry_id = 1000 + i;
    scene.meshes.back().specular = 0.15f;
  }

  // The prism instrument (seed Fig. 4): a blade with a round shaft rising from its top,
  // tilted back towards the viewer side like a hand would hold it. Local frame at the blade
  // centre; the pose places it.
  RenderMesh instrument = make_box(-l.blade_half, l.blade_half, colors.instrument);
  const Eigen::Vector3f shaft_base(0.0f, 0.0f, l.blade_half.z());
  const Eigen::Vector3f shaft_tip =
      shaft_base + l.shaft_length_m * Eigen::Vector3f(0.35f, -0.30f, 1.0f).normalized();
  append_mesh(instrument, make_cylinder(shaft_base, shaft_tip, 0.0012f, colors.instrument, 20));
  instrument.pose = Eigen::Translation3f(l.blade_center) *
                    Eigen::AngleAxisf(0.25f, Eigen::Vector3f::UnitZ());
  instrument.specular = 0.7f;
  instrument.geometry_id = 1005;
  scene.meshes.push_back(std::move(instrument));

  // A danger zone: translucent red sphere.
  scene.meshes.push_back(make_sphere(l.zone_center, l.zone_radius_m, colors.zone, 32));
  scene.meshes.back().specular = 0.3f;
  scene.meshes.back().geometry_id = 1006;

  // Particles on a cubic lattice filling the block; the spacing is chosen so the lattice
  // holds at least `particle_count` sites, then the first `particle_count` (bottom up) are kept.
  const Eigen::Vector3f size = l.block_max - l.block_min;
  const int n = std::max(particle_count, 0);
  if (n > 0) {
    float spacing = std::cbrt(size.prod() / static_cast<float>(n));
    Eigen::Vector3i cells;
    for (int iter = 0; iter < 64; ++iter) {
      for (int a = 0; a < 3; ++a) cells[a] = std::max(1, static_cast<int>(size[a] / spacing));
      if (static_cast<long>(cells.x()) * cells.y() * cells.z() >= n) break;
      spacing *= 0.97f;
    }
    scene.particles.radius_m = 0.5f * spacing;
    scene.particles.positions.reserve(n);
    scene.particles.colors.reserve(n);
    for (int k = 0; k < cells.z() && static_cast<int>(scene.particles.positions.size()) < n; ++k) {
      for (int j = 0; j < cells.y() && static_cast<int>(scene.particles.positions.size()) < n;
           ++j) {
        for (int i = 0; i < cells.x() && static_cast<int>(scene.particles.positions.size()) < n;
             ++i) {
          const Eigen::Vector3f p = l.block_min + spacing * Eigen::Vector3f(i, j, k) +
                                    Eigen::Vector3f::Constant(0.5f * spacing);
          scene.particles.positions.push_back(p);
          scene.particles.colors.push_back(colors.particles);
        }
      }
    }
  }

  scene.camera = frame_scene(scene, aspect);
  return scene;
}

}  // namespace acdr

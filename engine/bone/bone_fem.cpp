// Building a vertebra's elastic model and solving it for contact loads.
#include "engine/bone/bone_fem.hpp"

#include <chrono>
#include <cmath>
#include <limits>

namespace acdr {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace


std::unique_ptr<BoneFem> BoneFem::build(const TriangleMesh& surface, const SegmentParams& params,
                                        VertebraLevel level, const BoneFemConfig& config,
                                        const std::string& cache_dir, BoneFemReport* report,
                                        std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  BoneFemReport local;
  BoneFemReport& rep = report ? *report : local;
  rep = {};
  auto fail = [&](const std::string& why) -> std::unique_ptr<BoneFem> {
    if (error) *error = std::string(vertebra_level_name(level)) + ": " + why;
    return nullptr;
  };
  if (std::string bad = validate_bone_fem_config(config); !bad.empty()) {
    bad.pop_back();
    return fail("bad bone model configuration: " + bad);
  }

  std::unique_ptr<BoneFem> bone(new BoneFem());
  bone->config_ = config;
  bone->level_ = level;
  bone->body_ = vertebra_body_frame(params, level);
  std::string why;
  auto mesh = load_or_mesh_surface(surface, config.meshing, cache_dir, &rep.mesh, &why);
  if (!mesh) return fail(why);
  bone->mesh_ = std::move(*mesh);

  // Regions from geometry, then the material of every tetrahedron.
  auto t0 = std::chrono::steady_clock::now();
  bone->surface_ = std::make_unique<BoundarySurface>(bone->mesh_);
  bone->labels_ =
      classify_bone_regions(bone->mesh_, *bone->surface_, bone->body_, config.materials.shell);
  bone->mesh_.region = bone->labels_.region;
  std::vector<IsotropicMaterial> materials(bone->mesh_.tets.size()), stress(materials.size());
  for (std::size_t t = 0; t < materials.size(); ++t) {
    const auto region = static_cast<BoneRegion>(bone->labels_.region[t]);
    ++rep.region_tets[bone->labels_.region[t]];
    materials[t] = element_material(config.materials, region, bone->labels_.shell_fraction[t]);
    stress[t] = stress_material(config.materials, region);
  }

  // Supports: the surface on the far side of the body (up for C4, down for C5).
  const double far = level == VertebraLevel::kC4 ? 1.0 : -1.0;
  const double limit = bone->body_.half_height_m - config.support_depth_m;
  bone->fixed_.assign(bone->mesh_.nodes.size(), 0);
  for (std::size_t i = 0; i < bone->mesh_.nodes.size(); ++i) {
    if (!bone->surface_->on_surface()[i]) continue;
    if (far * (bone->mesh_.nodes[i].y() - bone->body_.center_m.y()) >= limit) {
      bone->fixed_[i] = kFixAll;
      ++rep.supported_nodes;
    }
  }
  rep.classify_seconds = seconds_since(t0);
  if (rep.supported_nodes == 0)
    return fail("no surface node lies on the far endplate: is the mesh in the segment frame?");

  bone->model_ = std::make_unique<ElasticModel>(bone->mesh_, materials, bone->fixed_, config.order,
                                                config.solver, stress);
  rep.elastic = bone->model_->report();
  if (!bone->model_->ok()) return fail(bone->model_->error());
  rep.total_seconds = seconds_since(start);
  return bone;
}

void BoneFem::solve(std::span<const ContactLoad> contacts, BoneSolution& out, bool nodal_fields,
                    const PartialSolve* partial) const {
  auto t0 = std::chrono::steady_clock::now();
  const std::size_t dofs = model_->dof_count(), nodes = mesh_.nodes.size(),
                    tets = mesh_.tets.size();
  out.force_N.assign(dofs, 0.0);
  out.dof_displacement_m.resize(dofs);
  out.contacts_applied = out.contacts_missed = 0;
  out.applied_force_N.setZero();
  for (const ContactLoad& c : contacts) {
    if (add_contact_load(model_->space(), *surface_, c, config_.max_snap_m, out.force_N,
                         out.faces)) {
      ++out.contacts_applied;
      out.applied_force_N += c.force_N;
    } else {
      ++out.contacts_missed;
    }
  }
  model_->solve(out.force_N, out.dof_displacement_m, out.workspace, partial);
  out.displacement_m.resize(nodes);
  for (std::size_t i = 0; i < nodes; ++i)
    out.displacement_m[i] = Vec3(out.dof_displacement_m[3 * i], out.dof_displacement_m[3 * i + 1],
                                 out.dof_displacement_m[3 * i + 2]);
  out.solve_seconds = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  out.element_stress_Pa.resize(tets);
  out.element_von_mises_Pa.resize(tets);
  if (partial) {
    // Only the elements asked for; the rest are marked as not computed.
    constexpr double kNotComputed = std::numeric_limits<double>::quiet_NaN();
    out.element_stress_Pa.assign(tets, Stress6::Constant(kNotComputed));
    out.element_von_mises_Pa.assign(tets, kNotComputed);
    model_->element_stress(out.dof_displacement_m, partial->elements, out.element_stress_Pa);
    for (std::uint32_t t : partial->elements)
      out.element_von_mises_Pa[t] = von_mises(out.element_stress_Pa[t]);
    out.node_von_mises_Pa.clear();
    out.stress_seconds = seconds_since(t0);
    return;
  }
  model_->element_stress(out.dof_displacement_m, out.element_stress_Pa);
  for (std::size_t t = 0; t < tets; ++t)
    out.element_von_mises_Pa[t] = von_mises(out.element_stress_Pa[t]);
  if (nodal_fields) {
    out.node_stress_Pa.resize(nodes);
    model_->nodal_stress(out.dof_displacement_m, out.element_stress_Pa, out.node_stress_Pa);
    out.node_von_mises_Pa.resize(nodes);
    for (std::size_t i = 0; i < nodes; ++i)
      out.node_von_mises_Pa[i] = von_mises(out.node_stress_Pa[i]);
  } else {
    out.node_von_mises_Pa.clear();
  }
  out.stress_seconds = seconds_since(t0);
}

}  // namespace acdr

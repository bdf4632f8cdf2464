// The scenario loader: a valid file gives the right SI values; each kind of error names the
// right line and JSON path, with what was found and what was expected.
#include "scenarios/scenario_loader.hpp"

#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <cmath>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <set>

#include "engine/nucleus/nucleus.hpp"
#include "engine/anatomy/vertebra_generator.hpp"
#include "scenarios/content_hash.hpp"
#include "scenarios/object_reader.hpp"
#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

using test::box_module_text;
using test::line_of;
using test::replace_once;

constexpr double kTol = 1e-12;

/// The errors of loading `text`; the test fails if it loads. Keep the vector alive while using
/// pointers from find_error.
std::vector<ScenarioError> errors_of(const std::string& text) {
  LoadResult r = load_scenario_text(text, "m.json");
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.model, nullptr);
  return r.errors;
}

/// The error at `path`, or a failed expectation listing all errors.
const ScenarioError* find_error(const std::vector<ScenarioError>& errors, const std::string& path) {
  for (const ScenarioError& e : errors) {
    if (e.json_path == path) return &e;
  }
  ADD_FAILURE() << "no error at " << path << "; got:\n" << to_string(errors);
  return nullptr;
}

// ---------------------------------------------------------------------------------------------
// Valid files

TEST(ScenarioLoader, BoxModuleLoadsWithSiValues) {
  const std::string text = box_module_text();
  const LoadResult r = load_scenario_text(text, "box.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  const ScenarioModel& m = *r.model;
  EXPECT_EQ(m.path, "box.json");
  EXPECT_EQ(m.hash, fnv1a64_hex(text));
  EXPECT_EQ(m.format_version, 1);
  EXPECT_EQ(m.id, "box-warmup");
  EXPECT_EQ(m.module_order, 1);
  EXPECT_FALSE(m.goal.empty());
  EXPECT_DOUBLE_EQ(m.time_limit_s, 60.0);

  const WorldConfig& w = m.world;
  EXPECT_NEAR(w.gravity_m_s2.z(), -9.80665, kTol);
  EXPECT_TRUE(w.ground.enabled);
  EXPECT_NEAR(w.ground.height_m, -0.002, kTol);
  EXPECT_TRUE(w.box.enabled);
  EXPECT_TRUE(w.box.inner_min_m.isApprox(Vec3(-0.015, -0.010, 0.0)));
  EXPECT_TRUE(w.box.inner_max_m.isApprox(Vec3(0.015, 0.010, 0.012)));
  EXPECT_NEAR(w.box.wall_thickness_m, 0.002, kTol);

  ASSERT_TRUE(w.nucleus.enabled);
  EXPECT_NEAR(w.nucleus.spacing_m, 0.002, kTol);
  EXPECT_DOUBLE_EQ(w.nucleus.bond_radius_factor, 1.5);
  ASSERT_EQ(w.nucleus.materials.size(), 1u);
  const MaterialConfig& mat = w.nucleus.materials[0];
  EXPECT_EQ(mat.name, "nucleus");
  EXPECT_DOUBLE_EQ(mat.density_kg_m3, 1050.0);
  EXPECT_DOUBLE_EQ(mat.viscosity_Pa_s, 250.0);
  EXPECT_DOUBLE_EQ(mat.bond_stiffness_N_m, 5.0);
  EXPECT_NEAR(mat.bond_break_m, 0.3e-3, kTol);
  EXPECT_DOUBLE_EQ(mat.surface_tension_N_m, 0.5);  // torn faces pull together in the box module
  EXPECT_EQ(mat.rebond_time_s, 0.0);                // (instead of re-bonding)
  EXPECT_TRUE(mat.counts_as_target);
  ASSERT_EQ(w.nucleus.blocks.size(), 1u);
  EXPECT_TRUE(w.nucleus.blocks[0].min_m.isApprox(Vec3(-0.015, -0.010, 0.0)));
  EXPECT_TRUE(w.nucleus.blocks[0].max_m.isApprox(Vec3(0.015, 0.010, 0.008)));
  EXPECT_EQ(w.nucleus.blocks[0].material, 0);

  const InstrumentConfig& in = w.instrument;
  EXPECT_TRUE(in.enabled);
  EXPECT_EQ(in.shape, InstrumentShape::kPrism);
  EXPECT_TRUE(in.blade_size_m.isApprox(Vec3(0.010, 0.006, 0.002)));
  EXPECT_NEAR(in.shaft_length_m, 0.080, kTol);
  EXPECT_NEAR(in.shaft_diameter_m, 0.002, kTol);
  EXPECT_NEAR(in.yield_stress_Pa, 500e6, 1e-3);
  EXPECT_DOUBLE_EQ(in.warning_fraction, 0.5);
  EXPECT_NEAR(in.mass_kg, 0.030, kTol);

  EXPECT_TRUE(w.instrument_start.position.isApprox(Vec3(0.0, 0.0, 0.110)));
  EXPECT_TRUE(w.instrument_start.orientation.isApprox(Quat::Identity()));
  EXPECT_DOUBLE_EQ(w.coupling.stiffness_N_m, 500.0);
  EXPECT_LT(w.coupling.damping_Ns_m, 0.0);  // absent: critically damped
  EXPECT_EQ(w.device.name, "Touch");
  EXPECT_DOUBLE_EQ(w.device.max_force_N, 3.3);
  EXPECT_NEAR(w.solver.dt_s, 1e-3, kTol);
  EXPECT_TRUE(w.removal.min_m.isApprox(Vec3(-0.015, -0.010, -0.001)));
  EXPECT_TRUE(w.removal.max_m.isApprox(Vec3(0.015, 0.010, 0.012)));

  ASSERT_EQ(m.rubric.terms.size(), 2u);
  EXPECT_EQ(m.rubric.terms[0].metric, "nucleus_removed_fraction");
  EXPECT_TRUE(m.rubric.terms[0].higher_is_better);
  EXPECT_EQ(m.rubric.terms[1].metric, "peak_instrument_force_N");
  EXPECT_FALSE(m.rubric.terms[1].higher_is_better);
  ASSERT_EQ(m.rubric.gates.size(), 1u);
  EXPECT_EQ(m.rubric.gates[0].metric, "overload_events");
  EXPECT_DOUBLE_EQ(m.rubric.gates[0].max, 0.0);
  EXPECT_DOUBLE_EQ(m.rubric.pass_score, 50.0);
  EXPECT_EQ(m.rubric.consecutive_passes_to_master, 2);
}

TEST(ScenarioLoader, OtherUnitSpellingsAndOptionsConvert) {
  const LoadResult r = load_scenario_file(test::source_path("tests/scenarios/data/complete.json"));
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  const WorldConfig& w = r.model->world;
  EXPECT_NEAR(w.ground.height_m, -0.003, kTol);
  EXPECT_NEAR(w.nucleus.spacing_m, 0.0015, kTol);
  EXPECT_NEAR(w.nucleus.materials[0].bond_break_m, 0.0004, kTol);
  EXPECT_NEAR(w.nucleus.materials[1].bond_break_m, 0.0002, kTol);
  EXPECT_NEAR(w.nucleus.materials[0].bulk_modulus_Pa, 25e3, 1e-9);
  EXPECT_NEAR(w.nucleus.materials[1].bulk_modulus_Pa, 60e3, 1e-9);
  EXPECT_NEAR(w.nucleus.materials[0].rebond_time_s, 0.02, 1e-12);
  EXPECT_NEAR(w.nucleus.materials[0].rebond_speed_m_s, 0.002, 1e-12);
  EXPECT_NEAR(w.nucleus.materials[1].rebond_time_s, 0.03, 1e-12);
  EXPECT_NEAR(w.nucleus.materials[1].rebond_speed_m_s, 0.003, 1e-12);
  EXPECT_NEAR(w.nucleus.materials[0].surface_tension_N_m, 0.07, 1e-12);
  EXPECT_EQ(w.nucleus.materials[1].surface_tension_N_m, 0.0);  // default: none
  EXPECT_FALSE(w.nucleus.materials[1].counts_as_target);
  EXPECT_EQ(w.nucleus.blocks[1].material, 1);  // by name
  EXPECT_EQ(w.instrument.shape, InstrumentShape::kCupCurette);
  EXPECT_NEAR(w.instrument.mass_kg, 0.045, kTol);
  EXPECT_NEAR(w.instrument.yield_stress_Pa, 800e6, 1e-3);
  EXPECT_NEAR(w.instrument.cup_diameter_m, 0.003, kTol);
  EXPECT_NEAR(w.instrument.cup_depth_m, 0.0015, kTol);
  EXPECT_NEAR(w.instrument.cup_wall_m, 0.0003, kTol);
  EXPECT_NEAR(w.instrument.cup_opening_angle_rad, 120.0 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(w.instrument.jaw_length_m, 0.008, kTol);
  EXPECT_NEAR(w.instrument.jaw_width_m, 0.002, kTol);
  EXPECT_NEAR(w.instrument.jaw_depth_m, 0.0008, kTol);
  EXPECT_NEAR(w.instrument.jaw_wall_m, 0.0003, kTol);
  EXPECT_NEAR(w.instrument.jaw_opening_rad, 40.0 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(w.instrument.jaw_angle_rad, 30.0 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(w.instrument.jaw_close_time_s, 0.3, 1e-12);
  EXPECT_FALSE(w.instrument.jaw_shake_off);
  // 30 degrees about +y.
  const Quat expected(std::cos(M_PI / 12), 0.0, std::sin(M_PI / 12), 0.0);
  EXPECT_TRUE(w.instrument_start.orientation.isApprox(expected, 1e-12));
  EXPECT_DOUBLE_EQ(w.coupling.damping_Ns_m, 4.0);
  EXPECT_DOUBLE_EQ(r.model->rubric.terms[0].sd_floor, 0.0);
  EXPECT_DOUBLE_EQ(r.model->rubric.terms[1].sd_floor, 0.02);
  // The preset's force is overridden, its name replaced.
  EXPECT_EQ(w.device.name, "bench Desktop");
  EXPECT_DOUBLE_EQ(w.device.max_force_N, 6.0);
  EXPECT_NEAR(w.device.max_jump_m, 0.02, kTol);
  EXPECT_NEAR(w.solver.dt_s, 0.0005, kTol);
  EXPECT_NEAR(w.solver.sleep_speed_m_s, 0.0002, kTol);
  EXPECT_FALSE(w.solver.sleep_enabled);
  EXPECT_EQ(r.model->rubric.consecutive_passes_to_master, 3);
}

TEST(ScenarioLoader, EveryModelFieldIsSettableFromTheFile) {
  // complete.json gives every field of ScenarioModel a value other than its default; a field
  // the loader forgot would keep its default and fail here.
  const LoadResult r = load_scenario_file(test::source_path("tests/scenarios/data/complete.json"));
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  const ScenarioModel& m = *r.model;
  const ScenarioModel d;
  EXPECT_NE(m.id, d.id);
  EXPECT_NE(m.title, d.title);
  EXPECT_NE(m.goal, d.goal);
  EXPECT_NE(m.module_order, d.module_order);
  EXPECT_NE(m.time_limit_s, d.time_limit_s);
  const WorldConfig& w = m.world;
  EXPECT_FALSE(w.gravity_m_s2.isApprox(d.world.gravity_m_s2));
  EXPECT_NE(w.ground.enabled, d.world.ground.enabled);
  EXPECT_NE(w.ground.height_m, d.world.ground.height_m);
  EXPECT_NE(w.box.enabled, d.world.box.enabled);
  EXPECT_NE(w.box.inner_min_m, d.world.box.inner_min_m);
  EXPECT_NE(w.box.inner_max_m, d.world.box.inner_max_m);
  EXPECT_NE(w.box.wall_thickness_m, d.world.box.wall_thickness_m);
  EXPECT_NE(w.nucleus.enabled, d.world.nucleus.enabled);
  EXPECT_NE(w.nucleus.spacing_m, d.world.nucleus.spacing_m);
  EXPECT_NE(w.nucleus.bond_radius_factor, d.world.nucleus.bond_radius_factor);
  ASSERT_EQ(w.nucleus.materials.size(), 2u);
  const MaterialConfig md;
  const MaterialConfig& annulus = w.nucleus.materials[1];
  EXPECT_NE(annulus.name, md.name);
  EXPECT_NE(annulus.density_kg_m3, md.density_kg_m3);
  EXPECT_NE(annulus.viscosity_Pa_s, md.viscosity_Pa_s);
  EXPECT_NE(annulus.bond_stiffness_N_m, md.bond_stiffness_N_m);
  EXPECT_NE(annulus.bond_break_m, md.bond_break_m);
  EXPECT_NE(annulus.bulk_modulus_Pa, md.bulk_modulus_Pa);
  EXPECT_NE(annulus.counts_as_target, md.counts_as_target);
  ASSERT_EQ(w.nucleus.blocks.size(), 2u);
  const ParticleBlockConfig bd;
  EXPECT_NE(w.nucleus.blocks[1].min_m, bd.min_m);
  EXPECT_NE(w.nucleus.blocks[1].max_m, bd.max_m);
  EXPECT_NE(w.nucleus.blocks[1].material, bd.material);
  const InstrumentConfig& in = w.instrument;
  const InstrumentConfig& id = d.world.instrument;
  EXPECT_NE(in.enabled, id.enabled);
  EXPECT_NE(in.shape, id.shape);
  EXPECT_NE(in.mass_kg, id.mass_kg);
  EXPECT_NE(in.shaft_length_m, id.shaft_length_m);
  EXPECT_NE(in.shaft_diameter_m, id.shaft_diameter_m);
  EXPECT_NE(in.yield_stress_Pa, id.yield_stress_Pa);
  EXPECT_NE(in.warning_fraction, id.warning_fraction);
  EXPECT_FALSE(in.blade_size_m.isApprox(id.blade_size_m));
  EXPECT_NE(in.cup_diameter_m, id.cup_diameter_m);
  EXPECT_NE(in.cup_depth_m, id.cup_depth_m);
  EXPECT_NE(in.cup_wall_m, id.cup_wall_m);
  EXPECT_NE(in.cup_opening_angle_rad, id.cup_opening_angle_rad);
  EXPECT_NE(in.jaw_length_m, id.jaw_length_m);
  EXPECT_NE(in.jaw_width_m, id.jaw_width_m);
  EXPECT_NE(in.jaw_depth_m, id.jaw_depth_m);
  EXPECT_NE(in.jaw_wall_m, id.jaw_wall_m);
  EXPECT_NE(in.jaw_opening_rad, id.jaw_opening_rad);
  EXPECT_NE(in.jaw_angle_rad, id.jaw_angle_rad);
  EXPECT_NE(in.jaw_close_time_s, id.jaw_close_time_s);
  EXPECT_NE(in.jaw_shake_off, id.jaw_shake_off);
  const CouplingConfig& cd = d.world.coupling;
  EXPECT_NE(w.coupling.stiffness_N_m, cd.stiffness_N_m);
  EXPECT_NE(w.coupling.damping_Ns_m, cd.damping_Ns_m);
  EXPECT_NE(w.coupling.rot_stiffness_Nm_rad, cd.rot_stiffness_Nm_rad);
  EXPECT_NE(w.coupling.rot_damping_Nms_rad, cd.rot_damping_Nms_rad);
  const DeviceConfig& dd = d.world.device;
  EXPECT_NE(w.device.name, dd.name);
  EXPECT_NE(w.device.max_force_N, dd.max_force_N);
  EXPECT_NE(w.device.max_force_rate_N_s, dd.max_force_rate_N_s);
  EXPECT_NE(w.device.ramp_in_s, dd.ramp_in_s);
  EXPECT_NE(w.device.max_jump_m, dd.max_jump_m);
  const SolverConfig& sd = d.world.solver;
  EXPECT_NE(w.solver.dt_s, sd.dt_s);
  EXPECT_NE(w.solver.nucleus_every, sd.nucleus_every);
  EXPECT_NE(w.solver.nucleus_pipelined, sd.nucleus_pipelined);
  EXPECT_NE(w.solver.max_iterations, sd.max_iterations);
  EXPECT_NE(w.solver.tolerance, sd.tolerance);
  EXPECT_NE(w.solver.sleep_enabled, sd.sleep_enabled);
  EXPECT_NE(w.solver.sleep_speed_m_s, sd.sleep_speed_m_s);
  EXPECT_NE(w.solver.sleep_distance_m, sd.sleep_distance_m);
  EXPECT_NE(w.removal.min_m, d.world.removal.min_m);
  EXPECT_NE(w.removal.max_m, d.world.removal.max_m);
  EXPECT_NE(w.instrument_start.position, d.world.instrument_start.position);
  EXPECT_FALSE(w.instrument_start.orientation.isApprox(d.world.instrument_start.orientation));
  const ParticleBlockConfig& shaped = w.nucleus.blocks[1];
  EXPECT_NE(shaped.shape, bd.shape);
  EXPECT_NE(shaped.axis, bd.axis);
  EXPECT_NE(shaped.center_m, bd.center_m);
  EXPECT_NE(shaped.semi_a_m, bd.semi_a_m);
  EXPECT_NE(shaped.semi_b_m, bd.semi_b_m);
  EXPECT_NE(shaped.hole_a_m, bd.hole_a_m);
  EXPECT_NE(shaped.hole_b_m, bd.hole_b_m);
  EXPECT_NE(shaped.has_cutout, bd.has_cutout);
  EXPECT_NE(shaped.cutout_min_m, bd.cutout_min_m);
  EXPECT_NE(shaped.cutout_max_m, bd.cutout_max_m);
  const AnatomyConfig& an = w.anatomy;
  const AnatomyConfig ad;
  EXPECT_NE(an.enabled, ad.enabled);
  EXPECT_NE(an.segment.disc_height_m, ad.segment.disc_height_m);
  EXPECT_NE(an.segment.facet_gap_m, ad.segment.facet_gap_m);
  EXPECT_NE(an.segment.mesh_spacing_m, ad.segment.mesh_spacing_m);
  const VertebraParams& v4 = an.segment.c4;
  const VertebraParams vd;
  EXPECT_NE(v4.endplate_width_m, vd.endplate_width_m);
  EXPECT_NE(v4.body_depth_m, vd.body_depth_m);
  EXPECT_NE(v4.body_height_m, vd.body_height_m);
  EXPECT_NE(v4.uncinate_height_m, vd.uncinate_height_m);
  EXPECT_NE(v4.uncinate_thickness_m, vd.uncinate_thickness_m);
  EXPECT_NE(v4.uncinate_depth_fraction, vd.uncinate_depth_fraction);
  EXPECT_NE(v4.pedicle_width_m, vd.pedicle_width_m);
  EXPECT_NE(v4.pedicle_height_m, vd.pedicle_height_m);
  EXPECT_NE(v4.canal_sagittal_m, vd.canal_sagittal_m);
  EXPECT_NE(v4.canal_transverse_m, vd.canal_transverse_m);
  EXPECT_NE(v4.foramen_transversarium_diameter_m, vd.foramen_transversarium_diameter_m);
  EXPECT_NE(v4.uncinate_to_foramen_m, vd.uncinate_to_foramen_m);
  EXPECT_NE(v4.foramen_anterior_offset_m, vd.foramen_anterior_offset_m);
  EXPECT_NE(v4.transverse_process_reach_m, vd.transverse_process_reach_m);
  EXPECT_NE(v4.lamina_thickness_m, vd.lamina_thickness_m);
  EXPECT_NE(v4.spinous_process_length_m, vd.spinous_process_length_m);
  EXPECT_NE(an.segment.c5.endplate_width_m, vd.endplate_width_m);
  EXPECT_NE(an.c4_mesh_path, ad.c4_mesh_path);
  EXPECT_NE(an.c5_mesh_path, ad.c5_mesh_path);
  EXPECT_NE(an.sdf.spacing_m, ad.sdf.spacing_m);
  EXPECT_NE(an.sdf.margin_m, ad.sdf.margin_m);
  EXPECT_NE(an.sdf.clip, ad.sdf.clip);
  EXPECT_NE(an.sdf.clip_min_m, ad.sdf.clip_min_m);
  EXPECT_NE(an.sdf.clip_max_m, ad.sdf.clip_max_m);
  EXPECT_NE(an.zone_sdf_spacing_m, ad.zone_sdf_spacing_m);
  EXPECT_NE(an.generate_zones, ad.generate_zones);
  const C4C5ZoneParams& zp = an.zone_params;
  const C4C5ZoneParams zd;
  EXPECT_NE(zp.artery_radius_m, zd.artery_radius_m);
  EXPECT_NE(zp.artery_warning_m, zd.artery_warning_m);
  EXPECT_NE(zp.artery_force_limit_N, zd.artery_force_limit_N);
  EXPECT_NE(zp.root_radius_m, zd.root_radius_m);
  EXPECT_NE(zp.root_warning_m, zd.root_warning_m);
  EXPECT_NE(zp.root_force_limit_N, zd.root_force_limit_N);
  EXPECT_NE(zp.cord_warning_m, zd.cord_warning_m);
  EXPECT_NE(zp.cord_force_limit_N, zd.cord_force_limit_N);
  EXPECT_NE(zp.endplate_warning_m, zd.endplate_warning_m);
  EXPECT_NE(zp.endplate_force_limit_N, zd.endplate_force_limit_N);
  EXPECT_NE(zp.endplate_depth_m, zd.endplate_depth_m);
  ASSERT_EQ(an.extra_zones.size(), 3u);
  const DangerZone& cap = an.extra_zones[0];
  const DangerZone& box = an.extra_zones[1];
  const DangerZone& band = an.extra_zones[2];
  const DangerZone zdef;
  EXPECT_NE(cap.name, zdef.name);
  EXPECT_NE(cap.shape, zdef.shape);
  EXPECT_NE(cap.a_m, zdef.a_m);
  EXPECT_NE(cap.b_m, zdef.b_m);
  EXPECT_NE(cap.radius_m, zdef.radius_m);
  EXPECT_NE(cap.never_event, zdef.never_event);
  EXPECT_NE(box.half_extents_m, zdef.half_extents_m);
  EXPECT_FALSE(box.orientation.isApprox(zdef.orientation));
  EXPECT_NE(band.bone, zdef.bone);
  EXPECT_NE(band.band_m, zdef.band_m);
  EXPECT_NE(band.region_min_m, zdef.region_min_m);
  EXPECT_NE(band.region_max_m, zdef.region_max_m);
  EXPECT_NE(band.warning_distance_m, zdef.warning_distance_m);
  EXPECT_NE(band.force_limit_N, zdef.force_limit_N);
  EXPECT_NE(an.cache_dir, ad.cache_dir);
  const Rubric& rd = d.rubric;
  ASSERT_EQ(m.rubric.terms.size(), 2u);
  const RubricTerm td;
  EXPECT_NE(m.rubric.terms[0].metric, td.metric);
  EXPECT_NE(m.rubric.terms[0].expert_mean, td.expert_mean);
  EXPECT_NE(m.rubric.terms[0].expert_sd, td.expert_sd);
  EXPECT_NE(m.rubric.terms[1].higher_is_better, td.higher_is_better);
  EXPECT_NE(m.rubric.terms[0].weight, td.weight);
  ASSERT_EQ(m.rubric.gates.size(), 2u);
  EXPECT_NE(m.rubric.gates[1].metric, SafetyGate().metric);
  EXPECT_NE(m.rubric.gates[1].max, SafetyGate().max);
  EXPECT_NE(m.rubric.pass_score, rd.pass_score);
  EXPECT_NE(m.rubric.consecutive_passes_to_master, rd.consecutive_passes_to_master);
}

TEST(ScenarioLoader, DefaultsApplyWhenKeysAreAbsent) {
  const std::string text = R"({
    "format_version": 1, "id": "minimal", "title": "t", "goal": "g",
    "world": { "instrument": {}, "device": { "max_force_N": 2 } },
    "rubric": { "terms": [ { "metric": "overload_events", "expert_mean": 0, "expert_sd": 1,
                             "higher_is_better": false } ],
                "gates": [ { "metric": "overload_events", "max": 0 } ] } })";
  const LoadResult r = load_scenario_text(text, "minimal.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  const ScenarioModel& m = *r.model;
  const InstrumentConfig defaults;
  EXPECT_TRUE(m.world.instrument.enabled);
  EXPECT_EQ(m.world.instrument.shape, InstrumentShape::kPrism);
  EXPECT_EQ(m.world.instrument.shaft_length_m, defaults.shaft_length_m);
  EXPECT_FALSE(m.world.nucleus.enabled);
  EXPECT_FALSE(m.world.box.enabled);
  EXPECT_EQ(m.world.device.name, "custom");
  EXPECT_DOUBLE_EQ(m.rubric.pass_score, 50.0);
  EXPECT_EQ(m.rubric.terms[0].weight, 1.0);
  EXPECT_EQ(m.time_limit_s, 0.0);
}

TEST(ScenarioLoader, IntegralFloatsCountAsIntegers) {
  const std::string with_cap = replace_once(box_module_text(), "\"tolerance\": 0.05",
                                            "\"tolerance\": 0.05, \"max_iterations\": 40");
  const std::string ok = replace_once(with_cap, "\"max_iterations\": 40", "\"max_iterations\": 40.0");
  const LoadResult r = load_scenario_text(ok, "m.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  EXPECT_EQ(r.model->world.solver.max_iterations, 40);
  const auto errors = errors_of(replace_once(with_cap, "\"max_iterations\": 40", "\"max_iterations\": 1.5"));
  const ScenarioError* e = find_error(errors, "/world/solver/max_iterations");
  ASSERT_NE(e, nullptr);
  EXPECT_NE(e->message.find("got 1.5, expected an integer"), std::string::npos) << e->message;
}

TEST(ScenarioLoader, ByteOrderMarkIsAccepted) {
  EXPECT_TRUE(load_scenario_text("\xEF\xBB\xBF" + box_module_text(), "bom.json").ok());
}

TEST(ScenarioLoader, EveryBundledModuleLoads) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_path("scenarios/modules"))) {
    if (entry.path().extension() != ".json") continue;
    const LoadResult r = load_scenario_file(entry.path().string());
    EXPECT_TRUE(r.ok()) << to_string(r.errors);
    ++count;
  }
  EXPECT_GE(count, 1);
}

// ---------------------------------------------------------------------------------------------
// Each kind of error

TEST(ScenarioLoaderErrors, UnknownKeySuggestsTheNearestKnownKey) {
  const std::string text = replace_once(box_module_text(), "\"spacing_mm\": 2", "\"spacnig_mm\": 2");
  const auto errors = errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << to_string(errors);
  EXPECT_EQ(errors[0].to_string(),
            "m.json:" + std::to_string(line_of(text, "spacnig_mm")) +
                ": /world/nucleus/spacnig_mm: unknown key (did you mean \"spacing_mm\" or \"spacing_m\"?)");
}

TEST(ScenarioLoaderErrors, UnknownKeyWithoutNearMatchListsTheKnownKeys) {
  const std::string text = replace_once(box_module_text(), "\"coupling\": { \"stiffness_N_m\": 500 }",
                                        "\"coupling\": { \"stiffness_N_m\": 500, \"zzz\": 1 }");
  const auto errors = errors_of(text);
  const ScenarioError* e = find_error(errors, "/world/coupling/zzz");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->line, line_of(text, "zzz"));
  EXPECT_NE(e->message.find("unknown key (expected one of: \"stiffness_N_m\""), std::string::npos);
}

TEST(ScenarioLoaderErrors, MissingRequiredKeyNamesThePathAndTheParentLine) {
  // A top-level key: reported at the root object's line.
  std::string text = replace_once(box_module_text(), "\"format_version\": 1,\n", "");
  auto errors = errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << to_string(errors);
  EXPECT_EQ(errors[0].to_string(), "m.json:1: /format_version: missing required key (expected an integer: the format version, 1)");

  // A nested key: at the line of the object that lacks it.
  text = replace_once(box_module_text(), "{ \"metric\": \"overload_events\", \"max\": 0 }", "{ \"max\": 0 }");
  errors = errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << to_string(errors);
  EXPECT_EQ(errors[0].json_path, "/rubric/gates/0/metric");
  EXPECT_EQ(errors[0].line, line_of(text, "{ \"max\": 0 }"));
  EXPECT_NE(errors[0].message.find("missing required key"), std::string::npos);
}

TEST(ScenarioLoaderErrors, WrongTypeSaysWhatWasFoundAndExpected) {
  const std::string text = replace_once(box_module_text(), "\"dt_ms\": 1", "\"dt_ms\": \"1\"");
  const auto errors = errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << to_string(errors);
  EXPECT_EQ(errors[0].to_string(), "m.json:" + std::to_string(line_of(text, "dt_ms")) +
                                       ": /world/solver/dt_ms: wrong type (got string \"1\", expected a number in ms)");
}

TEST(ScenarioLoaderErrors, WrongTypeInsideAVector) {
  const std::string text = replace_once(box_module_text(), "\"position_mm\": [0, 0, 110]",
                                        "\"position_mm\": [0, null, 110]");
  const auto errors = errors_of(text);
  const ScenarioError* e = find_error(errors, "/world/instrument_start/position_mm/1");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->message, "wrong type (got null, expected a number in mm)");
}

TEST(ScenarioLoaderErrors, OutOfRangeGivesTheBoundsInTheFileUnit) {
  const std::string text = replace_once(box_module_text(), "\"spacing_mm\": 2", "\"spacing_mm\": -1");
  const auto errors = errors_of(text);
  const ScenarioError* e = find_error(errors, "/world/nucleus/spacing_mm");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->line, line_of(text, "spacing_mm"));
  EXPECT_EQ(e->message, "out of range (got -1 mm, expected >= 0.1 mm and <= 10 mm)");
}

TEST(ScenarioLoaderErrors, RangeChecksOfManyKinds) {
  std::string text = box_module_text();
  text = replace_once(text, "\"density_kg_m3\": 1050", "\"density_kg_m3\": -5");
  text = replace_once(text, "\"viscosity_Pa_s\": 250", "\"viscosity_Pa_s\": -1");
  text = replace_once(text, "\"inner_max_mm\": [15, 10, 12]", "\"inner_max_mm\": [15, -20, 12]");
  text = replace_once(text, "\"warning_fraction\": 0.5", "\"warning_fraction\": 1.5");
  text = replace_once(text, "\"expert_sd\": 0.05", "\"expert_sd\": 0");
  text = replace_once(text, "\"pass_score\": 50", "\"pass_score\": 101");
  text = replace_once(text, "\"dt_ms\": 1", "\"dt_ms\": 0");
  const auto errors = errors_of(text);
  EXPECT_EQ(errors.size(), 7u) << to_string(errors);
  for (const char* path : {"/world/nucleus/materials/0/density_kg_m3", "/world/nucleus/materials/0/viscosity_Pa_s",
                           "/world/box/inner_max_mm", "/world/instrument/warning_fraction",
                           "/rubric/terms/0/expert_sd", "/rubric/pass_score", "/world/solver/dt_ms"}) {
    const ScenarioError* e = find_error(errors, path);
    if (e != nullptr) {
      EXPECT_GT(e->line, 1) << path;
    }
  }
  // Errors come sorted by line.
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LE(errors[i - 1].line, errors[i].line);
}

TEST(ScenarioLoader, RongeurShapeAndJaws) {
  std::string text = box_module_text();
  text = replace_once(text, "\"shape\": \"prism\"",
                      "\"shape\": \"rongeur\", \"jaw_length_mm\": 5, "
                      "\"jaw_width_mm\": 2.5, \"jaw_depth_mm\": 0.9, \"jaw_opening_angle_deg\": 45");
  const LoadResult r = load_scenario_text(text, "m.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  const InstrumentConfig& in = r.model->world.instrument;
  EXPECT_EQ(in.shape, InstrumentShape::kRongeur);
  EXPECT_TRUE(in.has_jaws());
  EXPECT_NEAR(in.jaw_length_m, 0.005, kTol);
  EXPECT_NEAR(in.jaw_width_m, 0.0025, kTol);
  EXPECT_NEAR(in.jaw_depth_m, 0.0009, kTol);
  EXPECT_NEAR(in.jaw_opening_rad, 45.0 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(in.jaw_angle_rad, 0.0);  // straight unless the scene bends them
}

TEST(ScenarioLoader, ATrayOfInstrumentsWithTheFirstInHand) {
  // Listed in the file order: the rongeur first, then the module's blade as it was.
  std::string text = replace_once(box_module_text(), "\"instrument\": {\n      \"shape\": \"prism\",",
                                  "\"instruments\": [{ \"name\": \"pituitary rongeur\", "
                                  "\"shape\": \"rongeur\", \"jaw_length_mm\": 5 }, {\n"
                                  "      \"name\": \"blade\", \"shape\": \"prism\",");
  text = replace_once(text, "\"mass_g\": 30\n    },", "\"mass_g\": 30\n    }],");
  const LoadResult r = load_scenario_text(text, "m.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  const WorldConfig& w = r.model->world;
  ASSERT_EQ(w.instruments.size(), 2u);
  EXPECT_EQ(w.instruments[0].name, "pituitary rongeur");
  EXPECT_EQ(w.instruments[0].shape, InstrumentShape::kRongeur);
  EXPECT_NEAR(w.instruments[0].jaw_length_m, 0.005, kTol);
  EXPECT_EQ(w.instruments[1].name, "blade");
  EXPECT_EQ(w.instruments[1].shape, InstrumentShape::kPrism);
  EXPECT_NEAR(w.instruments[1].blade_size_m.x(), 0.010, kTol);
  // The one in hand at the start is the first.
  EXPECT_TRUE(w.instrument.enabled);
  EXPECT_EQ(w.instrument.shape, InstrumentShape::kRongeur);
  EXPECT_EQ(w.instrument.name, "pituitary rongeur");
  // One instrument, as before: no tray.
  const LoadResult one = load_scenario_text(box_module_text(), "m.json");
  ASSERT_TRUE(one.ok());
  EXPECT_TRUE(one.model->world.instruments.empty());
}

TEST(ScenarioLoaderErrors, TrayErrorsNameTheInstrument) {
  // Both spellings at once.
  std::string both = replace_once(box_module_text(), "\"instrument_start\": {",
                                  "\"instruments\": [{ \"name\": \"a\" }, { \"name\": \"b\" }],\n"
                                  "    \"instrument_start\": {");
  auto errors = errors_of(both);
  const ScenarioError* e = find_error(errors, "/world/instruments");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->message, "give either \"instrument\" (one) or \"instruments\" (the tray), not both");
  // A name twice, a missing name, a shaft of its own, a tray of one.
  const std::string base = replace_once(box_module_text(), "\"instrument\": {\n      \"shape\": \"prism\",",
                                        "\"instruments\": [{ \"name\": \"cup\", \"shape\": \"cup_curette\" }, "
                                        "{ \"shape\": \"rongeur\" }, { \"name\": \"cup\" }, "
                                        "{ \"name\": \"thick\", \"shaft_diameter_mm\": 3 }, {\n"
                                        "      \"name\": \"blade\", \"shape\": \"prism\",");
  errors = errors_of(replace_once(base, "\"mass_g\": 30\n    },", "\"mass_g\": 30\n    }],"));
  const ScenarioError* unnamed = find_error(errors, "/world/instruments/1/name");
  ASSERT_NE(unnamed, nullptr);
  const ScenarioError* twice = find_error(errors, "/world/instruments/2/name");
  ASSERT_NE(twice, nullptr);
  EXPECT_EQ(twice->message, "instrument name used twice (got \"cup\", expected a name of its own)");
  const ScenarioError* thick = find_error(errors, "/world/instruments/3");
  ASSERT_NE(thick, nullptr);
  EXPECT_EQ(thick->message,
            "instrument \"thick\" has another shaft than the first (got diameter 3 mm, yield 500 "
            "MPa, warning 0.5; expected 2 mm, 500 MPa, 0.5: the record keeps one yield moment)");
  const std::string one = replace_once(box_module_text(), "\"instrument\": {\n      \"shape\": \"prism\",",
                                       "\"instruments\": [{\n      \"name\": \"blade\", \"shape\": \"prism\",");
  errors = errors_of(replace_once(one, "\"mass_g\": 30\n    },", "\"mass_g\": 30\n    }],"));
  const ScenarioError* few = find_error(errors, "/world/instruments");
  ASSERT_NE(few, nullptr);
  EXPECT_NE(few->message.find("too few items"), std::string::npos) << few->message;
}

TEST(ScenarioLoaderErrors, RongeurJawsOutOfShapeOrRange) {
  std::string text = box_module_text();
  text = replace_once(text, "\"shape\": \"prism\"",
                      "\"shape\": \"rongeur\", \"jaw_length_mm\": 2,\n"
                      "\"jaw_depth_mm\": 1.8,\n\"jaw_opening_angle_deg\": 150,\n\"jaw_angle_deg\": -15");
  const auto errors = errors_of(text);
  const ScenarioError* deep = find_error(errors, "/world/instrument/jaw_depth_mm");
  ASSERT_NE(deep, nullptr);
  EXPECT_EQ(deep->line, line_of(text, "jaw_depth_mm"));
  EXPECT_EQ(deep->message, "rongeur jaws deeper than long (got depth 1.8 mm + wall 0.4 mm, length "
                           "2 mm, expected depth + wall < length)");
  const ScenarioError* wide = find_error(errors, "/world/instrument/jaw_opening_angle_deg");
  ASSERT_NE(wide, nullptr);
  EXPECT_EQ(wide->message, "out of range (got 150 deg, expected >= 5 deg and <= 120 deg)");
  // The bend leans toward body +x; the other way is the instrument rolled about its shaft.
  const ScenarioError* bent = find_error(errors, "/world/instrument/jaw_angle_deg");
  ASSERT_NE(bent, nullptr);
  EXPECT_EQ(bent->line, line_of(text, "jaw_angle_deg"));
  EXPECT_EQ(bent->message, "out of range (got -15 deg, expected >= 0 deg and <= 90 deg)");
  // An unknown shape names the three.
  const auto shape = errors_of(replace_once(box_module_text(), "\"shape\": \"prism\"",
                                            "\"shape\": \"forceps\""));
  const ScenarioError* s = find_error(shape, "/world/instrument/shape");
  ASSERT_NE(s, nullptr);
  EXPECT_NE(s->message.find("\"rongeur\""), std::string::npos) << s->message;
}

TEST(ScenarioLoaderErrors, EmptiedArrayIsReported) {
  const std::string text = replace_once(box_module_text(),
                                        "\"gates\": [\n      { \"metric\": \"overload_events\", \"max\": 0 }\n    ]",
                                        "\"gates\": []");
  const auto errors = errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << to_string(errors);
  EXPECT_EQ(errors[0].json_path, "/rubric/gates");
  EXPECT_EQ(errors[0].line, line_of(text, "\"gates\""));
  EXPECT_EQ(errors[0].message, "too few items (got an array of 0 items, expected at least 1)");
}

TEST(ScenarioLoaderErrors, MalformedJsonNamesLineAndColumn) {
  const std::string text = replace_once(box_module_text(), "\"stiffness_N_m\": 500 }", "\"stiffness_N_m\": 500, }");
  const auto errors = errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << to_string(errors);
  EXPECT_EQ(errors[0].line, line_of(text, "\"stiffness_N_m\": 500, }"));
  EXPECT_GT(errors[0].column, 1);
  EXPECT_EQ(errors[0].json_path, "");
  EXPECT_NE(errors[0].message.find("malformed JSON at column " + std::to_string(errors[0].column)),
            std::string::npos) << errors[0].message;
}

TEST(ScenarioLoaderErrors, TruncatedFileNamesTheLastLine) {
  const std::string full = box_module_text();
  const std::string text = full.substr(0, full.find("\"instrument\""));
  const auto errors = errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << to_string(errors);
  // The position just after the last thing written (the comma closing the nucleus).
  EXPECT_EQ(errors[0].line, line_of(full, "\"instrument\"") - 1);
  EXPECT_NE(errors[0].message.find("the file ends before the JSON is complete"), std::string::npos);
}

TEST(ScenarioLoaderErrors, BothUnitSpellingsAtOnce) {
  const std::string text = replace_once(box_module_text(), "\"mass_g\": 30", "\"mass_g\": 30, \"mass_kg\": 0.03");
  const auto errors = errors_of(text);
  const ScenarioError* e = find_error(errors, "/world/instrument/mass_kg");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->message.rfind("give either \"mass_g\" or \"mass_kg\", not both", 0), 0u);
}

TEST(ScenarioLoaderErrors, UnknownEnumValueSuggests) {
  const std::string text = replace_once(box_module_text(), "\"preset\": \"Touch\"", "\"preset\": \"Tuch\"");
  const auto errors = errors_of(text);
  const ScenarioError* e = find_error(errors, "/world/device/preset");
  ASSERT_NE(e, nullptr);
  EXPECT_NE(e->message.find("did you mean \"Touch\"?"), std::string::npos) << e->message;
}

TEST(ScenarioLoaderErrors, UnknownMetricAndMaterialAreCaught) {
  std::string text = replace_once(box_module_text(), "\"metric\": \"overload_events\"", "\"metric\": \"overload_event\"");
  text = replace_once(text, "\"material\": \"nucleus\"", "\"material\": \"annulus\"");
  const auto errors = errors_of(text);
  const ScenarioError* metric = find_error(errors, "/rubric/gates/0/metric");
  ASSERT_NE(metric, nullptr);
  EXPECT_NE(metric->message.find("did you mean \"overload_events\"?"), std::string::npos);
  const ScenarioError* material = find_error(errors, "/world/nucleus/blocks/0/material");
  ASSERT_NE(material, nullptr);
  EXPECT_NE(material->message.find("expected one of \"nucleus\""), std::string::npos);
}

// Per-zone metrics are named "zone.<zone-id>.<quantity>": any such name loads, a
// malformed one is an error that states the pattern.
TEST(ScenarioLoaderErrors, ZoneMetricNamesFollowThePattern) {
  const std::string gate = "{ \"metric\": \"overload_events\", \"max\": 0 }";
  std::string text = replace_once(box_module_text(), gate,
                                   gate + ", { \"metric\": \"zone.spinal_cord_pll.peak_force_N\", \"max\": 1.5 }"
                                          ", { \"metric\": \"never_events\", \"max\": 0 }");
  const LoadResult ok = load_scenario_text(text, "zones.json");
  ASSERT_TRUE(ok.ok()) << to_string(ok.errors);
  ASSERT_EQ(ok.model->rubric.gates.size(), 3u);
  EXPECT_EQ(ok.model->rubric.gates[1].metric, "zone.spinal_cord_pll.peak_force_N");
  EXPECT_EQ(ok.model->rubric.gates[2].metric, "never_events");

  text = replace_once(box_module_text(), gate, "{ \"metric\": \"zone.Spinal Cord.peak_force\", \"max\": 0 }");
  const auto errors = errors_of(text);
  const ScenarioError* metric = find_error(errors, "/rubric/gates/0/metric");
  ASSERT_NE(metric, nullptr);
  EXPECT_NE(metric->message.find("or text matching ^zone"), std::string::npos) << metric->message;
}

// Safety terms score only when the attempt did the task, so a rubric with any must say what
// doing the task is; the bundled modules do, and gate on the danger zones.
TEST(ScenarioLoaderErrors, SafetyTermsNeedATaskRule) {
  const LoadResult box = load_scenario_text(box_module_text(), "box.json");
  ASSERT_TRUE(box.ok()) << to_string(box.errors);
  ASSERT_TRUE(box.model->rubric.task.has_value());
  EXPECT_EQ(box.model->rubric.task->metric, "nucleus_removed_fraction");
  EXPECT_DOUBLE_EQ(box.model->rubric.task->min, 0.04);
  EXPECT_FALSE(box.model->rubric.terms[0].safety);
  EXPECT_TRUE(box.model->rubric.terms[1].safety);

  const std::string task = "\"task\": { \"metric\": \"nucleus_removed_fraction\", \"min\": 0.04 },";
  const auto errors = errors_of(replace_once(box_module_text(), task, ""));
  const ScenarioError* e = find_error(errors, "/rubric/task");
  ASSERT_NE(e, nullptr);

  const auto bad_metric = errors_of(replace_once(box_module_text(), task,
      "\"task\": { \"metric\": \"nucleus_removed\", \"min\": 0.04 },"));
  EXPECT_NE(find_error(bad_metric, "/rubric/task/metric"), nullptr);

  for (const char* module : {"02_c4c5_healthy", "03_c4c5_degenerated", "04_full_discectomy"}) {
    const std::string path = test::source_path(std::string("scenarios/modules/") + module + ".json");
    const LoadResult m = load_scenario_file(path);
    ASSERT_TRUE(m.ok()) << to_string(m.errors);
    int safety = 0;
    for (const RubricTerm& t : m.model->rubric.terms) safety += t.safety;
    EXPECT_GE(safety, 4) << module << ": moment, zone dwell, zone impulse, protected material";
    bool gates_zones = false;
    for (const SafetyGate& g : m.model->rubric.gates) gates_zones |= g.metric == "zone_entries";
    EXPECT_TRUE(gates_zones) << module;
    ASSERT_TRUE(m.model->rubric.task.has_value()) << module;
  }
}

TEST(ScenarioLoaderErrors, DuplicateKeyIsNotSilentlyCollapsed) {
  const std::string text = replace_once(box_module_text(), "\"mass_g\": 30", "\"mass_g\": 30, \"mass_g\": 40");
  const auto errors = errors_of(text);
  const ScenarioError* e = find_error(errors, "/world/instrument/mass_g");
  ASSERT_NE(e, nullptr);
  EXPECT_NE(e->message.find("duplicate key"), std::string::npos);
}

TEST(ScenarioLoaderErrors, UnsupportedFormatVersion) {
  const auto errors = errors_of(replace_once(box_module_text(), "\"format_version\": 1", "\"format_version\": 2"));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].message, "unsupported format version (got 2, expected 1)");
}

TEST(ScenarioLoaderErrors, CrossChecks) {
  // Device without a preset must state its force.
  auto errors = errors_of(replace_once(box_module_text(), "\"preset\": \"Touch\"", "\"name\": \"mine\""));
  EXPECT_NE(find_error(errors, "/world/device/max_force_N"), nullptr);
  // A nucleus block outside the removal region would start out "removed".
  errors = errors_of(replace_once(box_module_text(), "\"min_mm\": [-15, -10, -1]", "\"min_mm\": [-15, -10, 1]"));
  const ScenarioError* e = find_error(errors, "/world/removal_region");
  ASSERT_NE(e, nullptr);
  EXPECT_NE(e->message.find("does not contain nucleus block 0"), std::string::npos);
  // Too fine a lattice for the block sizes.
  errors = errors_of(replace_once(box_module_text(), "\"spacing_mm\": 2", "\"spacing_mm\": 0.1"));
  e = find_error(errors, "/world/nucleus/blocks");
  ASSERT_NE(e, nullptr);
  EXPECT_NE(e->message.find("too many particles"), std::string::npos);
  // Not a rotation.
  errors = errors_of(replace_once(box_module_text(), "[1, 0, 0, 0]", "[1, 1, 0, 0]"));
  EXPECT_NE(find_error(errors, "/world/instrument_start/orientation_wxyz"), nullptr);
  // A nucleus needs a removal region.
  const std::string full = box_module_text();
  const std::size_t from = full.find(",\n    \"removal_region\"");
  const std::size_t to = full.find("}", full.find("\"max_mm\": [15, 10, 12]")) + 1;
  errors = errors_of(full.substr(0, from) + full.substr(to));
  EXPECT_NE(find_error(errors, "/world/removal_region"), nullptr);
}

TEST(ScenarioLoaderErrors, AllErrorsAreCollected) {
  std::string text = box_module_text();
  text = replace_once(text, "\"id\": \"box-warmup\"", "\"id\": \"Box Warmup\"");
  text = replace_once(text, "\"height_mm\": -2", "\"height_cm\": -2");
  text = replace_once(text, "\"shape\": \"prism\"", "\"shape\": 3");
  text = replace_once(text, "\"materials\": [", "\"materials\": [], \"x\": [");
  text = replace_once(text, "\"weight\": 1", "\"weight\": true");
  const auto errors = errors_of(text);
  for (const char* path : {"/id", "/world/ground/height_cm", "/world/instrument/shape", "/world/nucleus/materials",
                           "/world/nucleus/x", "/rubric/terms/0/weight"}) {
    EXPECT_NE(find_error(errors, path), nullptr);
  }
}

TEST(ScenarioLoaderErrors, NotAnObjectAndMissingFile) {
  auto errors = errors_of("[1, 2]");
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].to_string(), "m.json:1: wrong type (got an array of 2 items, expected an object)");
  const LoadResult r = load_scenario_file("/nonexistent/scenario.json");
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_NE(r.errors[0].message.find("cannot open"), std::string::npos);
  const LoadResult dir = load_scenario_file(test::source_path("scenarios"));
  ASSERT_EQ(dir.errors.size(), 1u);
  EXPECT_NE(dir.errors[0].message.find("not a regular file"), std::string::npos);
}

}  // namespace
}  // namespace acdr


namespace acdr {
namespace {

std::string healthy_module_text() {
  return test::read_text(test::source_path("scenarios/modules/02_c4c5_healthy.json"));
}

TEST(ScenarioLoaderAnatomy, BundledModulesLoadWithAnatomy) {
  for (const char* m : {"02_c4c5_healthy.json", "03_c4c5_degenerated.json", "04_full_discectomy.json"}) {
    const LoadResult r = load_scenario_file(test::source_path(std::string("scenarios/modules/") + m));
    ASSERT_TRUE(r.ok()) << to_string(r.errors);
    const WorldConfig& w = r.model->world;
    EXPECT_TRUE(w.anatomy.enabled) << m;
    EXPECT_TRUE(w.anatomy.generate_zones) << m;
    ASSERT_EQ(w.nucleus.blocks.size(), 4u) << m;  // nucleus, annulus, two cartilage endplates
    EXPECT_EQ(w.nucleus.blocks[0].shape, BlockShape::kEllipticCylinder);
    EXPECT_TRUE(w.nucleus.blocks[1].has_cutout);
    EXPECT_EQ(w.instrument.shape, InstrumentShape::kCupCurette);
  }
}

// The cartilage endplates (docs/anatomy.md, "Disc space") are one lattice layer against each
// bony endplate, on the nucleus's own lattice: no particle is doubled or crowded at the seams,
// every cartilage particle lies beyond every nucleus particle along the spine, and the nucleus
// keeps the four layers between them; the disc reaches the rims.
TEST(ScenarioLoaderAnatomy, CartilageEndplatesAreTheLayersAgainstTheBone) {
  for (const char* m : {"02_c4c5_healthy.json", "03_c4c5_degenerated.json", "04_full_discectomy.json"}) {
    const LoadResult r = load_scenario_file(test::source_path(std::string("scenarios/modules/") + m));
    ASSERT_TRUE(r.ok()) << to_string(r.errors);
    const WorldConfig& w = r.model->world;
    int nucleus_mat = -1, cartilage_mat = -1;
    for (std::size_t k = 0; k < w.nucleus.materials.size(); ++k) {
      if (w.nucleus.materials[k].name == "nucleus") nucleus_mat = static_cast<int>(k);
      if (w.nucleus.materials[k].name == "endplate_cartilage") cartilage_mat = static_cast<int>(k);
    }
    ASSERT_GE(nucleus_mat, 0) << m;
    ASSERT_GE(cartilage_mat, 0) << m;
    EXPECT_TRUE(w.nucleus.materials[nucleus_mat].counts_as_target) << m;
    EXPECT_FALSE(w.nucleus.materials[cartilage_mat].counts_as_target) << m;
    // No bone: the lattice as the blocks lay it out.
    const Nucleus n(w.nucleus, w.solver, Vec3::Zero(), {});
    const auto x = n.positions();
    const auto mat = n.materials();
    const double h = w.nucleus.spacing_m;
    double nucleus_lo = 1.0, nucleus_hi = -1.0;
    std::set<long> nucleus_layers;
    std::size_t cartilage = 0, nuclei = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      for (std::size_t j = i + 1; j < x.size(); ++j)
        ASSERT_GT((x[i] - x[j]).norm(), 0.999 * h) << m << ": particles " << i << " and " << j;
      if (mat[i] == nucleus_mat) {
        ++nuclei;
        nucleus_lo = std::min(nucleus_lo, x[i].y());
        nucleus_hi = std::max(nucleus_hi, x[i].y());
        nucleus_layers.insert(std::lround(x[i].y() / (0.01 * h)));
      }
    }
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (mat[i] != cartilage_mat) continue;
      ++cartilage;
      EXPECT_TRUE(x[i].y() < nucleus_lo - 0.99 * h || x[i].y() > nucleus_hi + 0.99 * h) << m;
      EXPECT_LT(std::abs(x[i].y()), 0.5 * w.anatomy.segment.disc_height_m) << m;
    }
    EXPECT_EQ(nucleus_layers.size(), 4u) << m;
    // Two layers of the nucleus's outline: half as many as the four nucleus layers.
    EXPECT_EQ(2 * cartilage, nuclei) << m;
    // The disc reaches the vertebral rims (16.1 x 16.1 mm endplates): annulus particles within
    // a lattice spacing or so of them at the sides and at the back (the front is the window).
    double reach_x = 0.0, back = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      reach_x = std::max(reach_x, std::abs(x[i].x()));
      back = std::min(back, x[i].z());
    }
    const double rim = 0.5 * w.anatomy.segment.c5.endplate_width_m;
    EXPECT_GT(reach_x, rim - 1.51 * h) << m;
    EXPECT_LT(back, -rim + 1.51 * h) << m;
    // ... and the nucleus takes 0.40 of the disc's area (docs/anatomy.md, "Disc space").
    const double nucleus_area = static_cast<double>(nuclei) / nucleus_layers.size() * h * h;
    EXPECT_NEAR(nucleus_area / (3.14159265 * 8e-3 * 8e-3), 0.40, 0.03) << m;
  }
}

// The table (ground plane) catches material dropped outside the field (without it a particle
// falls until the engine's blow-up check ends the attempt), and the specimen tray the expert
// wipes the cup on lies clear of the bone and outside the removal region (what is wiped off
// counts as removed). Checked against the generated vertebrae of each module's morphometry.
TEST(ScenarioLoaderAnatomy, TableAndTrayLieClearOfTheBone) {
  for (const char* m : {"02_c4c5_healthy.json", "03_c4c5_degenerated.json", "04_full_discectomy.json"}) {
    const LoadResult r = load_scenario_file(test::source_path(std::string("scenarios/modules/") + m));
    ASSERT_TRUE(r.ok()) << to_string(r.errors);
    const WorldConfig& w = r.model->world;
    ASSERT_TRUE(w.ground.enabled) << m;
    ASSERT_TRUE(w.box.enabled) << m;
    SegmentParams coarse = w.anatomy.segment;
    coarse.mesh_spacing_m = 1.0e-3;  // bounds to within a millimetre are enough here
    const Vec3 tray_lo = w.box.inner_min_m - Vec3::Constant(w.box.wall_thickness_m);
    const Vec3 tray_hi = w.box.inner_max_m + Vec3::Constant(w.box.wall_thickness_m);
    for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
      const TriangleMesh bone = generate_vertebra(coarse, level);
      Vec3 lo, hi;
      bone.bounds(&lo, &hi);
      EXPECT_LT(w.ground.height_m, lo.z() - 5e-3) << m;
      std::size_t inside_tray = 0;
      for (const Vec3& v : bone.vertices)
        if ((v.array() > tray_lo.array() - 1e-3).all() && (v.array() < tray_hi.array() + 1e-3).all())
          ++inside_tray;
      EXPECT_EQ(inside_tray, 0u) << m << ": bone within 1 mm of the tray";
    }
    // The whole tray lies outside the removal region (beyond it along some axis).
    const auto& rr = w.removal;
    EXPECT_TRUE((tray_lo.array() > rr.max_m.array()).any() || (tray_hi.array() < rr.min_m.array()).any()) << m;
  }
}

TEST(ScenarioLoaderAnatomy, BrokenMeshFileIsReportedWithItsPlace) {
  const std::string dir = test::source_path("tests/scenarios/data/");
  // A mesh file that does not parse: its own file and line appear in the error.
  const std::string bad = dir + "bone_broken.obj";
  {
    std::ofstream out(bad);
    out << "v 0 0 0\nv 1 0 0\nv 0 nope 0\nf 1 2 3\n";
  }
  const std::string text = replace_once(
      healthy_module_text(), R"("morphometry": { "disc_height_mm": 5.9, "c4": { "lip_resection_width_mm": 10 } },)",
      R"("morphometry": { "disc_height_mm": 5.9, "c4": { "lip_resection_width_mm": 10 } }, "meshes": { "c4": "bone_broken.obj", "c5": "bone_c5.stl", "units": "mm" },)");
  const LoadResult r = load_scenario_text(text, dir + "m.json");
  std::remove(bad.c_str());
  ASSERT_FALSE(r.ok());
  const std::string all = to_string(r.errors);
  EXPECT_NE(all.find("/world/anatomy/meshes"), std::string::npos) << all;
  EXPECT_NE(all.find("bone_broken.obj:3: vertex coordinate 2 is not a finite number (got 'nope')"),
            std::string::npos) << all;
}

TEST(ScenarioLoaderAnatomy, InconsistentMorphometryAndZones) {
  std::string text = replace_once(healthy_module_text(), R"("morphometry": { "disc_height_mm": 5.9, "c4": { "lip_resection_width_mm": 10 } },)",
                                  R"("morphometry": { "disc_height_mm": 5.9, "c5": { "uncinate_to_foramen_mm": 1.0 } },
      "zones": { "extra": [ { "name": "x", "shape": "capsule", "a_mm": [0, 0, 0], "radius_mm": 1,
                              "warning_mm": 1, "force_limit_N": 1, "never_event": true } ] },)");
  const LoadResult r = load_scenario_text(text, "m.json");
  ASSERT_FALSE(r.ok());
  const std::string all = to_string(r.errors);
  EXPECT_NE(all.find("inconsistent morphometry: c5.uncinate_to_foramen: got 1 mm"), std::string::npos) << all;
  EXPECT_NE(all.find("/world/anatomy/zones/extra/0"), std::string::npos) << all;  // b missing
  EXPECT_NE(all.find("b_mm"), std::string::npos) << all;
}

TEST(ScenarioLoaderAnatomy, ShapedBlocksAreChecked) {
  const std::string text = replace_once(healthy_module_text(), R"("hole_semi_axes_mm": [5.47, 4.68],)",
                                        R"("hole_semi_axes_mm": [8.5, 4.68],)");
  const LoadResult r = load_scenario_text(text, "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(to_string(r.errors).find("the hole must fit inside the ellipse"), std::string::npos)
      << to_string(r.errors);
}

// Every number has a practical range: a denormal is never a value, and a step below a
// tenth of a millisecond only costs time and memory.
TEST(ScenarioLoaderRanges, RefusesDenormalsAndStepsBelowThePhysicalFloor) {
  const std::string box = box_module_text();
  const int line = test::line_of(box, "\"solver\"");
  auto dt_error = [&](const std::string& value) {
    const auto errors = errors_of(replace_once(box, "\"dt_ms\": 1,", "\"dt_ms\": " + value + ","));
    EXPECT_EQ(errors.size(), 1u);
    return errors.empty() ? std::string() : errors[0].to_string();
  };
  EXPECT_EQ(dt_error("1e-320"), "m.json:" + std::to_string(line) +
                                    ": /world/solver/dt_ms: out of range (got 9.99988867e-321 ms, a denormal "
                                    "number, expected 0 or a normal number: >= 0.1 ms and <= 10 ms)");
  for (const char* tiny : {"0.001", "1e-6", "1e-9"}) {
    EXPECT_EQ(dt_error(tiny), "m.json:" + std::to_string(line) + ": /world/solver/dt_ms: out of range (got " +
                                  format_number(std::stod(tiny)) + " ms, expected >= 0.1 ms and <= 10 ms)");
  }
  EXPECT_TRUE(load_scenario_text(replace_once(box, "\"dt_ms\": 1,", "\"dt_ms\": 0.1,"), "m.json").ok());
  // The particles' own step (dt x nucleus_every) keeps to the same ceiling as dt.
  const std::string every = "\"dt_ms\": 1, \"nucleus_every\": ";
  EXPECT_TRUE(load_scenario_text(replace_once(box, "\"dt_ms\": 1,", every + "10,"), "m.json").ok());
  const auto slow = errors_of(replace_once(replace_once(box, "\"dt_ms\": 1,", every + "3,"),
                                           "\"dt_ms\": 1,", "\"dt_ms\": 4,"));
  ASSERT_EQ(slow.size(), 1u);
  EXPECT_NE(slow[0].to_string().find("/world/solver/nucleus_every: nucleus_every 3 at dt 4 ms "
                                     "steps the particles at 12 ms (expected at most 10 ms)"),
            std::string::npos)
      << slow[0].to_string();
  // A denormal where zero is allowed (a viscosity of 0 is a physical value).
  const auto errors = errors_of(replace_once(box, "\"viscosity_Pa_s\": 250", "\"viscosity_Pa_s\": 4e-320"));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].message.find("a denormal number"), std::string::npos) << errors[0].message;
  EXPECT_TRUE(load_scenario_text(replace_once(box, "\"viscosity_Pa_s\": 250", "\"viscosity_Pa_s\": 0"), "m.json").ok());
}

// A mesh path that leads to a device or a FIFO is refused at once, as the scenario file is.
TEST(ScenarioLoaderFiles, RefusesMeshesThatAreDevicesOrFifos) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "acdr_scenario_special_meshes";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::create_symlink("/dev/zero", dir / "zero.stl");
  fs::create_symlink("/dev/urandom", dir / "random.obj");
  ASSERT_EQ(::mkfifo((dir / "pipe.stl").c_str(), 0600), 0);
  fs::copy_file(test::source_path("tests/scenarios/data/bone_c5.stl"), dir / "bone_c5.stl");
  const std::string complete = test::read_text(test::source_path("tests/scenarios/data/complete.json"));
  for (const char* name : {"zero.stl", "random.obj", "pipe.stl"}) {
    SCOPED_TRACE(name);
    const std::string text = replace_once(complete, "\"c4\": \"bone_c4.obj\"", std::string("\"c4\": \"") + name + "\"");
    const std::string path = (dir / "scenario.json").string();
    std::ofstream(path, std::ios::binary) << text;
    const auto t0 = std::chrono::steady_clock::now();
    const LoadResult r = load_scenario_file(path);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
    ASSERT_FALSE(r.ok());
    const std::string all = to_string(r.errors);
    EXPECT_NE(all.find("/world/anatomy/meshes: " + (dir / name).string() + ": not a regular file (got a "),
              std::string::npos) << all;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acdr

namespace acdr {
namespace {

// anatomy.bone: the finite-element vertebrae. The anatomical modules turn it on, the box
// module has none; every key converts its unit; bad values, both spellings, materials that
// are not materials and a bone metric in a rubric without the bone are errors with their place.
const std::string kBoneKeys = R"("bone": { "element_size_mm": 1.5, "sample_period_ms": 10 })";

TEST(ScenarioLoaderBone, AnatomicalModulesModelTheBoneAndTheBoxDoesNot) {
  for (const char* m : {"02_c4c5_healthy.json", "03_c4c5_degenerated.json", "04_full_discectomy.json"}) {
    const LoadResult r = load_scenario_file(test::source_path(std::string("scenarios/modules/") + m));
    ASSERT_TRUE(r.ok()) << to_string(r.errors);
    EXPECT_TRUE(r.model->bone.enabled) << m;
    EXPECT_DOUBLE_EQ(r.model->bone.fem.meshing.size_m, 1.5e-3) << m;
    EXPECT_DOUBLE_EQ(r.model->world.anatomy.bone_load_period_s, 0.01) << m;
  }
  const LoadResult box = load_scenario_file(test::source_path("scenarios/modules/01_box_warmup.json"));
  ASSERT_TRUE(box.ok()) << to_string(box.errors);
  EXPECT_FALSE(box.model->bone.enabled);
  EXPECT_EQ(box.model->world.anatomy.bone_load_period_s, 0.0);
}

TEST(ScenarioLoaderBone, EveryKeyConvertsToSi) {
  const std::string text = replace_once(healthy_module_text(), kBoneKeys, R"("bone": {
        "element_size_m": 0.002, "order": "quadratic", "support_depth_mm": 1.5,
        "sample_period_s": 0.02, "nucleus_cell_mm": 3,
        "materials": {
          "cortical": { "youngs_modulus_MPa": 10000, "poisson_ratio": 0.29, "thickness_mm": 0.3 },
          "cancellous": { "youngs_modulus_Pa": 2e8 },
          "endplate": { "youngs_modulus_MPa": 500, "thickness_mm": 0.6 },
          "posterior": { "poisson_ratio": 0.25 }
        },
        "strength": { "endplate_MPa": 10, "posterior_Pa": 3e7, "warning_fraction": 0.6 }
      })");
  const LoadResult r = load_scenario_text(text, "m.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  const BoneModelConfig& b = r.model->bone;
  EXPECT_TRUE(b.enabled);
  EXPECT_DOUBLE_EQ(b.fem.meshing.size_m, 0.002);
  EXPECT_EQ(b.fem.order, TetOrder::kQuadratic);
  EXPECT_DOUBLE_EQ(b.fem.support_depth_m, 1.5e-3);
  EXPECT_DOUBLE_EQ(b.sample_period_s, 0.02);
  EXPECT_DOUBLE_EQ(b.nucleus_cell_m, 3e-3);
  EXPECT_DOUBLE_EQ(b.fem.materials.cortical.youngs_modulus_Pa, 10e9);
  EXPECT_DOUBLE_EQ(b.fem.materials.cortical.poisson_ratio, 0.29);
  EXPECT_DOUBLE_EQ(b.fem.materials.shell.cortical_thickness_m, 0.3e-3);
  EXPECT_DOUBLE_EQ(b.fem.materials.cancellous.youngs_modulus_Pa, 2e8);
  EXPECT_DOUBLE_EQ(b.fem.materials.endplate.youngs_modulus_Pa, 500e6);
  EXPECT_DOUBLE_EQ(b.fem.materials.shell.endplate_thickness_m, 0.6e-3);
  EXPECT_DOUBLE_EQ(b.fem.materials.posterior.poisson_ratio, 0.25);
  EXPECT_DOUBLE_EQ(b.fem.materials.posterior.youngs_modulus_Pa, 3.5e9);  // default kept
  EXPECT_DOUBLE_EQ(b.strengths.endplate_Pa, 10e6);
  EXPECT_DOUBLE_EQ(b.strengths.posterior_Pa, 3e7);
  EXPECT_DOUBLE_EQ(b.strengths.warning_fraction, 0.6);
  // The world samples loads at the bone's period, gathering the nucleus over its cells.
  EXPECT_DOUBLE_EQ(r.model->world.anatomy.bone_load_period_s, 0.02);
  EXPECT_DOUBLE_EQ(r.model->world.anatomy.bone_load_cell_m, 3e-3);
  // Turned off: the keys stay valid, nothing is sampled.
  // (its rubric's term on the endplate stress goes with it: a bone metric needs the bone)
  const LoadResult off = load_scenario_text(
      replace_once(replace_once(healthy_module_text(), kBoneKeys,
                                R"("bone": { "enabled": false, "element_size_mm": 2 })"),
                   R"("metric": "endplate_peak_stress_MPa")", R"("metric": "peak_contact_force_N")"),
      "m.json");
  ASSERT_TRUE(off.ok()) << to_string(off.errors);
  EXPECT_FALSE(off.model->bone.enabled);
  EXPECT_EQ(off.model->world.anatomy.bone_load_period_s, 0.0);
}

TEST(ScenarioLoaderBone, BadValuesAreErrorsWithTheirPlace) {
  const std::string text = replace_once(healthy_module_text(), kBoneKeys, R"("bone": {
        "element_size_mm": 0.1, "element_size_m": 0.002, "order": "cubic",
        "sample_period_ms": 0,
        "materials": { "cancellous": { "poisson_ratio": 0.5, "density": 1 } },
        "strength": { "warning_fraction": 1.5 }
      })");
  const std::vector<ScenarioError> errors = errors_of(text);
  const std::string all = to_string(errors);
  // Both spellings of one quantity.
  EXPECT_NE(all.find("element_size"), std::string::npos) << all;
  find_error(errors, "/world/anatomy/bone/order");
  find_error(errors, "/world/anatomy/bone/sample_period_ms");
  find_error(errors, "/world/anatomy/bone/materials/cancellous/poisson_ratio");
  find_error(errors, "/world/anatomy/bone/materials/cancellous/density");  // unknown key
  find_error(errors, "/world/anatomy/bone/strength/warning_fraction");
  EXPECT_NE(all.find("cubic"), std::string::npos) << all;
  EXPECT_NE(all.find("quadratic"), std::string::npos) << all;  // what was expected
}

TEST(ScenarioLoaderBone, ABoneMetricNeedsTheBoneModel) {
  std::string text = replace_once(healthy_module_text(), kBoneKeys, R"("bone": { "enabled": false })");
  text = replace_once(text, R"("gates": [)",
                      R"("gates": [ { "metric": "endplate_peak_stress_MPa", "max": 5 },)");
  const std::vector<ScenarioError> errors = errors_of(text);
  const ScenarioError* e = find_error(errors, "/rubric/gates/0/metric");
  ASSERT_NE(e, nullptr);
  EXPECT_NE(e->message.find("bone metric without a bone model"), std::string::npos) << e->message;
  // With the bone model on, the same gate loads.
  const std::string on = replace_once(healthy_module_text(), R"("gates": [)",
                                      R"("gates": [ { "metric": "endplate_peak_stress_MPa", "max": 5 },)");
  const LoadResult r = load_scenario_text(on, "m.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  EXPECT_EQ(r.model->rubric.gates[0].metric, "endplate_peak_stress_MPa");
}

}  // namespace
}  // namespace acdr

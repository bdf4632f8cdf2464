// The scenario loader: parse, index positions, then read the format top-down with typed,
// located reads (object_reader.hpp), collecting every error. Defaults, units and ranges here
// are the ones documented in docs/scenario-format.md and scenarios/scenario.schema.json.
#include "scenarios/scenario_loader.hpp"

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/anatomy/anatomy.hpp"
#include "engine/bone/bone_segment.hpp"
#include "scenarios/content_hash.hpp"
#include "scenarios/device_presets.hpp"
#include "scenarios/json_position_index.hpp"
#include "assessment/metric_catalog.hpp"
#include "scenarios/object_reader.hpp"
#include "scenarios/scenario_cost.hpp"

namespace acdr {

using nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------------
// Unit spellings. A quantity with two natural units accepts both, never both at once.

std::vector<UnitKey> length(const std::string& base) {
  return {{base + "_mm", 1e-3, "mm"}, {base + "_m", 1.0, "m"}};
}
std::vector<UnitKey> mass(const std::string& base) {
  return {{base + "_g", 1e-3, "g"}, {base + "_kg", 1.0, "kg"}};
}
std::vector<UnitKey> stress(const std::string& base) {
  return {{base + "_MPa", 1e6, "MPa"}, {base + "_Pa", 1.0, "Pa"}};
}
std::vector<UnitKey> modulus(const std::string& base) {
  return {{base + "_kPa", 1e3, "kPa"}, {base + "_Pa", 1.0, "Pa"}};
}
std::vector<UnitKey> duration(const std::string& base) {
  return {{base + "_ms", 1e-3, "ms"}, {base + "_s", 1.0, "s"}};
}
std::vector<UnitKey> speed(const std::string& base) {
  return {{base + "_mm_s", 1e-3, "mm/s"}, {base + "_m_s", 1.0, "m/s"}};
}
std::vector<UnitKey> plain(const std::string& key, const char* symbol = "") {
  return {{key, 1.0, symbol}};
}

constexpr double kMm = 1e-3;
/// Coordinates: anywhere within 10 m of the origin (a scene is centimetres across).
const Range kCoordinate = Range::closed(-10.0, 10.0);
/// Forces a zone allows: from a tenth of what a hand can feel reliably to well above a device's.
const Range kForceLimit = Range::closed(0.001, 100.0);
/// The shortest step: 10 kHz, ten times the haptic rate (a finer step only costs time and
/// memory: one recorded frame per step).
constexpr double kMinStep = 0.1e-3;
/// Rubric figures (expert means, gate limits): any metric's value fits well within this.
const Range kMetricValue = Range::closed(-1e9, 1e9);

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

std::string vec_text(const Vec3& v, double scale, const char* unit) {
  return "[" + format_number(v.x() / scale) + ", " + format_number(v.y() / scale) + ", " +
         format_number(v.z() / scale) + "] " + unit;
}

/// Which spelling of a vector key the file used (for messages about cross-checks).
std::string used_key(const ObjectReader& r, const std::string& base) {
  return r.has(base + "_m") ? base + "_m" : base + "_mm";
}

/// min < max on every axis, else an error on the max key.
bool check_box(ObjectReader& r, const std::string& min_base, const std::string& max_base,
               const Vec3& min, const Vec3& max) {
  if ((min.array() < max.array()).all()) return true;
  r.context().error(r.child(used_key(r, max_base)),
                    "must exceed " + in_quotes(used_key(r, min_base)) + " on every axis (got min " +
                        vec_text(min, kMm, "mm") + ", max " + vec_text(max, kMm, "mm") +
                        ", expected max > min for x, y and z)");
  return false;
}

// ---------------------------------------------------------------------------------------------
// world parts

void read_ground(ObjectReader& r, GroundConfig& g) {
  g.enabled = true;
  if (auto h = r.quantity(length("height"), Need::kOptional, kCoordinate)) g.height_m = *h;
  r.finish();
}

void read_box(ObjectReader& r, OpenBoxConfig& b) {
  b.enabled = true;
  auto min = r.vector3(length("inner_min"), Need::kRequired, kCoordinate);
  auto max = r.vector3(length("inner_max"), Need::kRequired, kCoordinate);
  if (min && max && check_box(r, "inner_min", "inner_max", *min, *max)) {
    b.inner_min_m = *min;
    b.inner_max_m = *max;
  }
  if (auto t = r.quantity(length("wall_thickness"), Need::kOptional, Range::closed(0.1 * kMm, 50 * kMm))) {
    b.wall_thickness_m = *t;
  }
  r.finish();
}

void read_material(ObjectReader& r, MaterialConfig& m) {
  if (auto s = r.string("name", Need::kRequired, true, {}, "the material name")) m.name = *s;
  if (auto v = r.number("density_kg_m3", Need::kOptional, Range::closed(10.0, 20000.0), "kg/m³")) {
    m.density_kg_m3 = *v;
  }
  if (auto v = r.number("viscosity_Pa_s", Need::kOptional, Range::closed(0.0, 1e6), "Pa·s")) {
    m.viscosity_Pa_s = *v;
  }
  if (auto v = r.number("bond_stiffness_N_m", Need::kOptional, Range::closed(0.0, 1e5), "N/m")) {
    m.bond_stiffness_N_m = *v;
  }
  if (auto v = r.quantity(length("bond_break"), Need::kOptional, Range::closed(0.001 * kMm, 10 * kMm))) {
    m.bond_break_m = *v;
  }
  if (auto v = r.quantity(modulus("bulk_modulus"), Need::kOptional, Range::closed(1.0, 1e9))) {
    m.bulk_modulus_Pa = *v;
  }
  if (auto v = r.quantity(duration("rebond_time"), Need::kOptional, Range::closed(0.0, 10.0))) {
    m.rebond_time_s = *v;
  }
  if (auto v = r.quantity(speed("rebond_speed"), Need::kOptional, Range::closed(1e-6, 1.0))) {
    m.rebond_speed_m_s = *v;
  }
  if (auto v = r.number("surface_tension_N_m", Need::kOptional, Range::closed(0.0, 1.0), "N/m")) {
    m.surface_tension_N_m = *v;
  }
  if (auto v = r.boolean("counts_as_target", Need::kOptional)) m.counts_as_target = *v;
  r.finish();
}

// anatomy: block shapes for the disc space

/// The optional shape of a nucleus block: an elliptic cylinder (the nucleus) or ring (the
/// annulus) inside the block's box, and an optional cut-out (the annular window).
void read_block_shape(ObjectReader& br, ParticleBlockConfig& b) {
  if (auto s = br.string("shape", Need::kOptional, true, {"box", "elliptic_cylinder"},
                         "the region's shape")) {
    b.shape = *s == "box" ? BlockShape::kBox : BlockShape::kEllipticCylinder;
  }
  if (auto s = br.string("axis", Need::kOptional, true, {"x", "y", "z"}, "the cylinder's axis")) {
    b.axis = *s == "x" ? 0 : *s == "y" ? 1 : 2;
  }
  const bool elliptic = b.shape == BlockShape::kEllipticCylinder;
  if (auto c = br.vector3(length("center"), Need::kOptional, kCoordinate)) b.center_m = *c;
  else b.center_m = 0.5 * (b.min_m + b.max_m);
  if (auto v = br.numbers("semi_axes_mm", elliptic ? Need::kRequiredHere : Need::kOptional, 2)) {
    // Bounds as for every length of a block: from a fraction of a lattice spacing to the box.
    auto practical = [](double mm) { return mm >= 0.1 && mm <= 10000.0; };
    if (practical((*v)[0]) && practical((*v)[1])) {
      b.semi_a_m = (*v)[0] * kMm;
      b.semi_b_m = (*v)[1] * kMm;
    } else {
      br.context().error(br.child("semi_axes_mm"), "semi-axes out of range (got [" +
                                                       format_number((*v)[0]) + ", " + format_number((*v)[1]) +
                                                       "] mm, expected two lengths from 0.1 mm to 10000 mm)");
    }
  }
  if (auto v = br.numbers("hole_semi_axes_mm", Need::kOptional, 2)) {
    if ((*v)[0] >= 0 && (*v)[1] >= 0 && (*v)[0] * kMm < b.semi_a_m && (*v)[1] * kMm < b.semi_b_m) {
      b.hole_a_m = (*v)[0] * kMm;
      b.hole_b_m = (*v)[1] * kMm;
    } else {
      br.context().error(br.child("hole_semi_axes_mm"),
                         "the hole must fit inside the ellipse (got [" + format_number((*v)[0]) + ", " +
                             format_number((*v)[1]) + "] mm, expected each >= 0 and below semi_axes_mm)");
    }
  }
  auto cmin = br.vector3(length("cutout_min"), Need::kOptional, kCoordinate);
  auto cmax = br.vector3(length("cutout_max"), cmin ? Need::kRequiredHere : Need::kOptional, kCoordinate);
  if (cmin && cmax && check_box(br, "cutout_min", "cutout_max", *cmin, *cmax)) {
    b.has_cutout = true;
    b.cutout_min_m = *cmin;
    b.cutout_max_m = *cmax;
  }
}

// anatomy: vertebrae, bone distance grid, danger zones

void read_vertebra(ObjectReader& r, VertebraParams& v) {
  // Each size in the range the generator builds (engine/anatomy/vertebra_generator.cpp,
  // validate_segment_params); how the sizes must relate to each other is checked there.
  auto set = [&](const char* base, double& field, double min_mm, double max_mm) {
    if (auto x = r.quantity(length(base), Need::kOptional, Range::closed(min_mm * kMm, max_mm * kMm))) field = *x;
  };
  set("endplate_width", v.endplate_width_m, 5, 40);
  set("body_depth", v.body_depth_m, 5, 40);
  set("body_height", v.body_height_m, 5, 30);
  set("uncinate_height", v.uncinate_height_m, 0.1, 30);
  set("uncinate_thickness", v.uncinate_thickness_m, 0.5, 10);
  if (auto x = r.number("uncinate_depth_fraction", Need::kOptional, Range::closed(0.1, 1.0))) {
    v.uncinate_depth_fraction = *x;
  }
  set("pedicle_width", v.pedicle_width_m, 1, 15);
  set("pedicle_height", v.pedicle_height_m, 1, 30);
  set("canal_sagittal", v.canal_sagittal_m, 5, 30);
  set("canal_transverse", v.canal_transverse_m, 10, 40);
  set("foramen_transversarium_diameter", v.foramen_transversarium_diameter_m, 1, 12);
  set("uncinate_to_foramen", v.uncinate_to_foramen_m, 1, 20);
  set("foramen_anterior_offset", v.foramen_anterior_offset_m, 0, 40);
  set("transverse_process_reach", v.transverse_process_reach_m, 1, 20);
  set("lamina_thickness", v.lamina_thickness_m, 1, 8);
  set("spinous_process_length", v.spinous_process_length_m, 2, 40);
  set("superior_concavity", v.superior_concavity_m, 0, 5);
  set("anterior_lip", v.anterior_lip_m, 0, 5);
  set("lip_resection_width", v.lip_resection_width_m, 0, 40);
  r.finish();
}

void read_morphometry(ObjectReader& r, SegmentParams& p) {
  if (auto x = r.quantity(length("disc_height"), Need::kOptional, Range::closed(2 * kMm, 15 * kMm))) p.disc_height_m = *x;
  if (auto x = r.quantity(length("facet_gap"), Need::kOptional, Range::closed(0.2 * kMm, 5 * kMm))) p.facet_gap_m = *x;
  if (auto x = r.quantity(length("mesh_spacing"), Need::kOptional, Range::closed(0.1 * kMm, 2 * kMm))) {
    p.mesh_spacing_m = *x;
  }
  if (auto o = r.object("c4", Need::kOptional)) read_vertebra(*o, p.c4);
  if (auto o = r.object("c5", Need::kOptional)) read_vertebra(*o, p.c5);
  // Cross-checks between the sizes (the foramen outside the uncinate process, ...).
  const std::string problems = validate_segment_params(p);
  std::istringstream lines(problems);
  for (std::string line; std::getline(lines, line);) {
    r.context().error(r.pointer(), "inconsistent morphometry: " + line);
  }
  r.finish();
}

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

void read_meshes(ObjectReader& r, AnatomyConfig& a, const std::string& scenario_path) {
  // Paths relative to the scenario file, like "$schema".
  auto path = [&](const char* key, std::string& out) {
    if (auto s = r.string(key, Need::kRequired, true, {}, "a mesh file (.obj or .stl)")) {
      out = (!s->empty() && (*s)[0] == '/') ? *s : directory_of(scenario_path) + *s;
    }
  };
  path("c4", a.c4_mesh_path);
  path("c5", a.c5_mesh_path);
  if (auto u = r.string("units", Need::kRequired, true, {"mm", "m"}, "the unit the files are written in")) {
    a.mesh_unit_m = *u == "mm" ? 1e-3 : 1.0;
  }
  // Open or broken meshes are reported now, with the file's own line or byte.
  if (!a.c4_mesh_path.empty() && !a.c5_mesh_path.empty()) {
    std::istringstream lines(check_anatomy_files(a));
    for (std::string line; std::getline(lines, line);) r.context().error(r.pointer(), line);
  }
  r.finish();
}

void read_sdf(ObjectReader& r, AnatomyConfig& a) {
  if (auto x = r.quantity(length("spacing"), Need::kOptional, Range::closed(0.05 * kMm, 2 * kMm))) a.sdf.spacing_m = *x;
  if (auto x = r.quantity(length("margin"), Need::kOptional, Range::closed(0.0, 20 * kMm))) a.sdf.margin_m = *x;
  if (auto x = r.quantity(length("zone_spacing"), Need::kOptional, Range::closed(0.05 * kMm, 2 * kMm))) {
    a.zone_sdf_spacing_m = *x;
  }
  auto min = r.vector3(length("region_min"), Need::kOptional, kCoordinate);
  auto max = r.vector3(length("region_max"), min ? Need::kRequiredHere : Need::kOptional, kCoordinate);
  if (min && max && check_box(r, "region_min", "region_max", *min, *max)) {
    a.sdf.clip = true;
    a.sdf.clip_min_m = *min;
    a.sdf.clip_max_m = *max;
  }
  r.finish();
}

/// Defaults of one kind of generated zone.
void read_zone_defaults(ObjectReader& r, double* radius, double* warning, double* force, double* depth) {
  if (radius) {
    if (auto x = r.quantity(length("radius"), Need::kOptional, Range::closed(0.1 * kMm, 20 * kMm))) *radius = *x;
  }
  if (auto x = r.quantity(length("warning"), Need::kOptional, Range::closed(0.0, 20 * kMm))) *warning = *x;
  if (auto x = r.number("force_limit_N", Need::kOptional, kForceLimit, "N")) *force = *x;
  if (depth) {
    if (auto x = r.quantity(length("depth"), Need::kOptional, Range::closed(0.1 * kMm, 20 * kMm))) *depth = *x;
  }
  r.finish();
}

void read_zone(ObjectReader& r, DangerZone& z) {
  if (auto s = r.string("name", Need::kRequired, true, {}, "the zone's name, shown with its events")) z.name = *s;
  std::string shape = "sphere";
  if (auto s = r.string("shape", Need::kRequired, true, {"sphere", "capsule", "box", "bone_band"},
                        "the zone's shape")) {
    shape = *s;
  }
  z.shape = shape == "sphere" ? ZoneShape::kSphere : shape == "capsule" ? ZoneShape::kCapsule
          : shape == "box"    ? ZoneShape::kBox    : ZoneShape::kSdfBand;
  const bool point = shape == "sphere" || shape == "capsule" || shape == "box";
  // Which keys a zone needs depends on its shape (kRequiredHere: required for this item only).
  if (auto a = r.vector3(length("a"), point ? Need::kRequiredHere : Need::kOptional, kCoordinate)) z.a_m = *a;
  if (auto b = r.vector3(length("b"), shape == "capsule" ? Need::kRequiredHere : Need::kOptional, kCoordinate)) z.b_m = *b;
  if (auto c = r.vector3(length("c"), Need::kOptional, kCoordinate)) {
    z.c_m = *c;
    z.bent = shape == "capsule";
  }
  if (auto x = r.quantity(length("radius"), shape == "sphere" || shape == "capsule" ? Need::kRequiredHere : Need::kOptional,
                          Range::closed(0.1 * kMm, 50 * kMm))) {
    z.radius_m = *x;
  }
  if (auto e = r.vector3(length("half_extents"), shape == "box" ? Need::kRequiredHere : Need::kOptional,
                         Range::closed(0.1 * kMm, 100 * kMm))) {
    z.half_extents_m = *e;
    if (z.radius_m > z.half_extents_m.minCoeff()) {
      r.context().error(r.child("radius_mm"), "a box's rounding cannot exceed its smallest half extent (got " +
                                                  format_number(z.radius_m / kMm) + " mm, expected at most " +
                                                  format_number(z.half_extents_m.minCoeff() / kMm) + " mm)");
    }
  }
  if (auto q = r.numbers("orientation_wxyz", Need::kOptional, 4)) {
    const Quat quat((*q)[0], (*q)[1], (*q)[2], (*q)[3]);
    if (std::fabs(quat.norm() - 1.0) > 1e-3) {
      r.context().error(r.child("orientation_wxyz"), "not a unit quaternion (got norm " + format_number(quat.norm()) +
                                                         ", expected 1 within 0.001)");
    } else {
      z.orientation = quat.normalized();
    }
  }
  if (auto s = r.string("bone", shape == "bone_band" ? Need::kRequiredHere : Need::kOptional, true, {"c4", "c5"},
                        "the vertebra whose surface the band follows")) {
    z.bone = *s == "c4" ? 0 : 1;
  }
  if (auto x = r.quantity(length("band"), Need::kOptional, Range::closed(0.0, 20 * kMm))) z.band_m = *x;
  auto rmin = r.vector3(length("region_min"), shape == "bone_band" ? Need::kRequiredHere : Need::kOptional, kCoordinate);
  auto rmax = r.vector3(length("region_max"), shape == "bone_band" ? Need::kRequiredHere : Need::kOptional, kCoordinate);
  if (rmin && rmax && check_box(r, "region_min", "region_max", *rmin, *rmax)) {
    z.region_min_m = *rmin;
    z.region_max_m = *rmax;
  }
  if (auto x = r.quantity(length("warning"), Need::kRequired, Range::closed(0.0, 20 * kMm))) z.warning_distance_m = *x;
  if (auto x = r.number("force_limit_N", Need::kRequired, kForceLimit, "N")) z.force_limit_N = *x;
  if (auto b = r.boolean("never_event", Need::kRequired)) z.never_event = *b;
  r.finish();
}

void read_zones(ObjectReader& r, AnatomyConfig& a) {
  if (auto b = r.boolean("generate", Need::kOptional)) a.generate_zones = *b;
  C4C5ZoneParams& zp = a.zone_params;
  if (auto o = r.object("vertebral_artery", Need::kOptional)) {
    read_zone_defaults(*o, &zp.artery_radius_m, &zp.artery_warning_m, &zp.artery_force_limit_N, nullptr);
  }
  if (auto o = r.object("nerve_root", Need::kOptional)) {
    read_zone_defaults(*o, &zp.root_radius_m, &zp.root_warning_m, &zp.root_force_limit_N, nullptr);
  }
  if (auto o = r.object("spinal_cord_pll", Need::kOptional)) {
    read_zone_defaults(*o, nullptr, &zp.cord_warning_m, &zp.cord_force_limit_N, nullptr);
  }
  if (auto o = r.object("endplates", Need::kOptional)) {
    read_zone_defaults(*o, nullptr, &zp.endplate_warning_m, &zp.endplate_force_limit_N, &zp.endplate_depth_m);
  }
  for (ObjectReader& zr : r.objects("extra", Need::kOptional, 0)) {
    DangerZone z;
    read_zone(zr, z);
    a.extra_zones.push_back(z);
  }
  const int total = (a.generate_zones ? 7 : 0) + static_cast<int>(a.extra_zones.size());
  if (total > kMaxZones) {
    r.context().error(r.child("extra"), "too many zones (got " + std::to_string(total) + " with the " +
                                            (a.generate_zones ? "7 generated" : "0 generated") +
                                            ", expected at most " + std::to_string(kMaxZones) + ")");
  }
  r.finish();
}

// anatomy.bone: the vertebrae as finite-element solids (engine/bone, docs/bone-fem.md)

void read_bone_material(ObjectReader& r, IsotropicMaterial& m, double* thickness_m) {
  if (auto x = r.quantity(stress("youngs_modulus"), Need::kOptional, Range::positive(100e9))) {
    m.youngs_modulus_Pa = *x;
  }
  if (auto x = r.number("poisson_ratio", Need::kOptional, {0.0, 0.5, false, true})) m.poisson_ratio = *x;
  if (thickness_m != nullptr) {
    if (auto x = r.quantity(length("thickness"), Need::kOptional, Range::positive(5 * kMm))) *thickness_m = *x;
  }
  r.finish();
}

void read_bone(ObjectReader& r, BoneModelConfig& b) {
  b.enabled = true;
  if (auto v = r.boolean("enabled", Need::kOptional)) b.enabled = *v;
  BoneFemConfig& f = b.fem;
  if (auto x = r.quantity(length("element_size"), Need::kOptional, Range::closed(1.0 * kMm, 5 * kMm))) {
    f.meshing.size_m = *x;
  }
  if (auto s = r.string("order", Need::kOptional, true, {"linear", "quadratic"},
                        "the tetrahedra's order")) {
    f.order = *s == "quadratic" ? TetOrder::kQuadratic : TetOrder::kLinear;
  }
  if (auto x = r.quantity(length("support_depth"), Need::kOptional, Range::positive(5 * kMm))) {
    f.support_depth_m = *x;
  }
  if (auto x = r.quantity(duration("sample_period"), Need::kOptional, Range::closed(1e-3, 1.0))) {
    b.sample_period_s = *x;
  }
  if (auto x = r.quantity(length("nucleus_cell"), Need::kOptional, Range::closed(0.5 * kMm, 10 * kMm))) {
    b.nucleus_cell_m = *x;
  }
  if (auto o = r.object("materials", Need::kOptional)) {
    BoneMaterials& m = f.materials;
    if (auto c = o->object("cortical", Need::kOptional)) read_bone_material(*c, m.cortical, &m.shell.cortical_thickness_m);
    if (auto c = o->object("cancellous", Need::kOptional)) read_bone_material(*c, m.cancellous, nullptr);
    if (auto c = o->object("endplate", Need::kOptional)) read_bone_material(*c, m.endplate, &m.shell.endplate_thickness_m);
    if (auto c = o->object("posterior", Need::kOptional)) read_bone_material(*c, m.posterior, nullptr);
    o->finish();
  }
  if (auto o = r.object("strength", Need::kOptional)) {
    if (auto x = o->quantity(stress("endplate"), Need::kOptional, Range::positive(1e9))) b.strengths.endplate_Pa = *x;
    if (auto x = o->quantity(stress("posterior"), Need::kOptional, Range::positive(1e9))) b.strengths.posterior_Pa = *x;
    if (auto x = o->number("warning_fraction", Need::kOptional, Range::positive(1.0))) {
      b.strengths.warning_fraction = *x;
    }
    o->finish();
  }
  // What the keys cannot say one by one (e.g. the materials' own checks).
  std::istringstream lines(validate_bone_model_config(b));
  for (std::string line; std::getline(lines, line);) {
    r.context().error(r.pointer(), "bad bone model: " + line);
  }
  r.finish();
}

void read_anatomy(ObjectReader& r, AnatomyConfig& a, BoneModelConfig& bone,
                  const std::string& scenario_path) {
  a.enabled = true;
  if (auto o = r.object("morphometry", Need::kOptional)) read_morphometry(*o, a.segment);
  if (auto o = r.object("meshes", Need::kOptional)) read_meshes(*o, a, scenario_path);
  if (auto o = r.object("sdf", Need::kOptional)) read_sdf(*o, a);
  if (auto o = r.object("zones", Need::kOptional)) read_zones(*o, a);
  if (auto b = r.boolean("posterior_ligament", Need::kOptional)) a.posterior_ligament = *b;
  if (auto s = r.string("cache_dir", Need::kOptional, true, {},
                        "a directory for cached meshes and grids, or \"none\"")) {
    a.cache_dir = *s;
  }
  if (auto o = r.object("bone", Need::kOptional)) read_bone(*o, bone);
  if (bone.enabled) {
    a.bone_load_period_s = bone.sample_period_s;
    a.bone_load_cell_m = bone.nucleus_cell_m;
  }
  r.finish();
}

void read_nucleus(ObjectReader& r, NucleusConfig& n) {
  n.enabled = true;
  if (auto h = r.quantity(length("spacing"), Need::kOptional, Range::closed(0.1 * kMm, 10 * kMm))) {
    n.spacing_m = *h;
  }
  // Above 1 so that nearest neighbours (at exactly h) bond; 3 h already bonds ~100 neighbours.
  if (auto f = r.number("bond_radius_factor", Need::kOptional, {1.0, 3.0, true, false})) {
    n.bond_radius_factor = *f;
  }
  std::vector<ObjectReader> materials = r.objects("materials", Need::kRequired, 1);
  for (ObjectReader& mr : materials) {
    MaterialConfig m;
    read_material(mr, m);
    const bool duplicate = std::any_of(n.materials.begin(), n.materials.end(),
                                       [&](const MaterialConfig& o) { return o.name == m.name; });
    if (duplicate) {
      r.context().error(mr.child("name"), "duplicate material name (got " + in_quotes(m.name) +
                                              ", expected a name not used by another material)");
    }
    n.materials.push_back(m);
  }

  std::vector<ObjectReader> blocks = r.objects("blocks", Need::kRequired, 1);
  for (ObjectReader& br : blocks) {
    ParticleBlockConfig b;
    auto min = br.vector3(length("min"), Need::kRequired, kCoordinate);
    auto max = br.vector3(length("max"), Need::kRequired, kCoordinate);
    if (min && max && check_box(br, "min", "max", *min, *max)) {
      b.min_m = *min;
      b.max_m = *max;
    }
    read_block_shape(br, b);
    // A material by name (preferred) or by index into `materials`.
    const json* mat = br.raw("material", Need::kOptional, "integer|string",
                             "a material name or index");
    if (mat != nullptr) {
      std::string names;
      for (std::size_t i = 0; i < n.materials.size(); ++i) {
        names += (i == 0 ? "" : ", ") + in_quotes(n.materials[i].name);
      }
      if (mat->is_string()) {
        const std::string& s = mat->get_ref<const std::string&>();
        auto it = std::find_if(n.materials.begin(), n.materials.end(),
                               [&](const MaterialConfig& m) { return m.name == s; });
        if (it == n.materials.end()) {
          br.context().error(br.child("material"), "unknown material (got " + describe_value(*mat) +
                                                       ", expected one of " + names + ")");
        } else {
          b.material = static_cast<int>(it - n.materials.begin());
        }
      } else if (mat->is_number_integer() ||
                 (mat->is_number_float() && std::floor(mat->get<double>()) == mat->get<double>())) {
        const double i = mat->get<double>();
        if (i < 0 || i >= static_cast<double>(n.materials.size())) {
          br.context().error(br.child("material"),
                             "no such material (got index " + describe_value(*mat) + ", expected 0 to " +
                                 std::to_string(static_cast<int>(n.materials.size()) - 1) + ": " +
                                 names + ")");
        } else {
          b.material = static_cast<int>(i);
        }
      } else {
        br.context().error(br.child("material"), "wrong type (got " + describe_value(*mat) +
                                                     ", expected a material name or index)");
      }
    }
    br.finish();
    n.blocks.push_back(b);
  }

  r.finish();
}

// A pituitary rongeur's jaws (InstrumentConfig): sizes, opening and how fast the hand closes
// them.
void read_rongeur_jaws(ObjectReader& r, InstrumentConfig& in) {
  if (auto v = r.quantity(length("jaw_length"), Need::kOptional, Range::closed(1 * kMm, 30 * kMm))) {
    in.jaw_length_m = *v;
  }
  if (auto v = r.quantity(length("jaw_width"), Need::kOptional, Range::closed(0.5 * kMm, 10 * kMm))) {
    in.jaw_width_m = *v;
  }
  if (auto v = r.quantity(length("jaw_depth"), Need::kOptional, Range::closed(0.1 * kMm, 5 * kMm))) {
    in.jaw_depth_m = *v;
  }
  if (auto v = r.quantity(length("jaw_wall"), Need::kOptional, Range::closed(0.05 * kMm, 3 * kMm))) {
    in.jaw_wall_m = *v;
  }
  if (auto v = r.number("jaw_opening_angle_deg", Need::kOptional, Range::closed(5.0, 120.0),
                        "deg")) {
    in.jaw_opening_rad = *v * M_PI / 180.0;
  }
  // Angled (up-biting) jaws: bent off the shaft in their opening plane; 0 straight.
  if (auto v = r.number("jaw_angle_deg", Need::kOptional, Range::closed(0.0, 90.0), "deg")) {
    in.jaw_angle_rad = *v * M_PI / 180.0;
  }
  if (auto v = r.number("jaw_close_time_s", Need::kOptional, Range::closed(0.01, 5.0), "s")) {
    in.jaw_close_time_s = *v;
  }
  if (auto b = r.boolean("jaw_shake_off", Need::kOptional)) in.jaw_shake_off = *b;
  // The jaws' outer faces when closed stand depth + wall off the axis: the jaws must fit
  // through their own width in the window, and stay thinner than their length.
  if (in.has_jaws() && !(in.jaw_depth_m + in.jaw_wall_m < in.jaw_length_m)) {
    const std::string key = r.has("jaw_depth_m") ? "jaw_depth_m" : "jaw_depth_mm";
    r.context().error(r.child(key), "rongeur jaws deeper than long (got depth " +
                                        format_number(in.jaw_depth_m / kMm) + " mm + wall " +
                                        format_number(in.jaw_wall_m / kMm) + " mm, length " +
                                        format_number(in.jaw_length_m / kMm) +
                                        " mm, expected depth + wall < length)");
  }
}

void read_instrument(ObjectReader& r, InstrumentConfig& in) {
  in.enabled = true;
  if (auto s = r.string("shape", Need::kOptional, true, {"prism", "cup_curette", "rongeur"})) {
    in.shape = *s == "prism"         ? InstrumentShape::kPrism
               : *s == "cup_curette" ? InstrumentShape::kCupCurette
                                     : InstrumentShape::kRongeur;
  }
  if (auto v = r.quantity(mass("mass"), Need::kOptional, Range::closed(1e-3, 5.0))) in.mass_kg = *v;
  if (auto v = r.quantity(length("shaft_length"), Need::kOptional, Range::closed(5 * kMm, 0.5))) {
    in.shaft_length_m = *v;
  }
  if (auto v = r.quantity(length("shaft_diameter"), Need::kOptional, Range::closed(0.1 * kMm, 20 * kMm))) {
    in.shaft_diameter_m = *v;
  }
  if (auto v = r.quantity(stress("yield_stress"), Need::kOptional, Range::closed(1e6, 5000e6))) {
    in.yield_stress_Pa = *v;
  }
  if (auto v = r.number("warning_fraction", Need::kOptional, Range::closed(0.01, 1.0))) {
    in.warning_fraction = *v;
  }
  if (auto v = r.vector3(length("blade_size"), Need::kOptional, Range::closed(0.1 * kMm, 100 * kMm))) {
    in.blade_size_m = *v;
  }
  if (auto v = r.quantity(length("cup_diameter"), Need::kOptional, Range::closed(0.1 * kMm, 20 * kMm))) {
    in.cup_diameter_m = *v;
  }
  if (auto v = r.quantity(length("cup_depth"), Need::kOptional, Range::closed(0.1 * kMm, 20 * kMm))) {
    in.cup_depth_m = *v;
  }
  // 90 deg: a straight curette opening sideways; up to 180 deg: angled back toward the handle.
  if (auto v = r.number("cup_opening_angle_deg", Need::kOptional, Range::closed(90.0, 180.0),
                        "deg")) {
    in.cup_opening_angle_rad = *v * M_PI / 180.0;
  }
  auto wall = r.quantity(length("cup_wall"), Need::kOptional, Range::closed(0.01 * kMm, 5 * kMm));
  if (wall) in.cup_wall_m = *wall;
  if (2.0 * in.cup_wall_m >= in.cup_diameter_m) {
    const std::string key = r.has("cup_wall_m") ? "cup_wall_m" : "cup_wall_mm";
    r.context().error(r.child(key), "cup wall too thick for the cup (got wall " +
                                        format_number(in.cup_wall_m / kMm) + " mm, diameter " +
                                        format_number(in.cup_diameter_m / kMm) +
                                        " mm, expected twice the wall < the diameter)");
  }
  read_rongeur_jaws(r, in);
  r.finish();
}

// The instruments on the tray (world.instruments): each as world.instrument, with a name; the
// first is in hand at the start. The record keeps one yield moment for the shaft, so they share
// the shaft's diameter, yield stress and warning fraction.
void read_instruments(ObjectReader& r, WorldConfig& w) {
  std::vector<ObjectReader> items = r.objects("instruments", Need::kOptional, 2);
  if (items.empty()) return;
  if (r.has("instrument")) {
    r.context().error(r.child("instruments"),
                      "give either \"instrument\" (one) or \"instruments\" (the tray), not both");
    return;
  }
  for (ObjectReader& o : items) {
    InstrumentConfig in;
    if (auto name = o.string("name", Need::kRequired)) in.name = *name;
    read_instrument(o, in);
    for (const InstrumentConfig& other : w.instruments) {
      if (other.name == in.name) {
        o.context().error(o.child("name"), "instrument name used twice (got \"" + in.name +
                                               "\", expected a name of its own)");
      }
    }
    const InstrumentConfig& first = w.instruments.empty() ? in : w.instruments.front();
    if (in.shaft_diameter_m != first.shaft_diameter_m || in.yield_stress_Pa != first.yield_stress_Pa ||
        in.warning_fraction != first.warning_fraction) {
      o.context().error(o.pointer(), "instrument \"" + in.name +
                                         "\" has another shaft than the first (got diameter " +
                                         format_number(in.shaft_diameter_m / kMm) + " mm, yield " +
                                         format_number(in.yield_stress_Pa / 1e6) + " MPa, warning " +
                                         format_number(in.warning_fraction) + "; expected " +
                                         format_number(first.shaft_diameter_m / kMm) + " mm, " +
                                         format_number(first.yield_stress_Pa / 1e6) + " MPa, " +
                                         format_number(first.warning_fraction) +
                                         ": the record keeps one yield moment)");
    }
    w.instruments.push_back(in);
  }
  w.instrument = w.instruments.front();
}

void read_instrument_start(ObjectReader& r, Pose& pose) {
  if (auto p = r.vector3(length("position"), Need::kOptional, kCoordinate)) pose.position = *p;
  // Orientation: a unit quaternion [w, x, y, z], or an axis and an angle in degrees.
  auto q = r.numbers("orientation_wxyz", Need::kOptional, 4);
  std::optional<ObjectReader> aa = r.object("orientation_axis_angle", Need::kOptional);
  if (q && aa) {
    r.context().error(r.child("orientation_axis_angle"),
                      "give either \"orientation_wxyz\" or \"orientation_axis_angle\", not both");
  } else if (q) {
    const double norm = std::sqrt((*q)[0] * (*q)[0] + (*q)[1] * (*q)[1] + (*q)[2] * (*q)[2] +
                                  (*q)[3] * (*q)[3]);
    // Tolerant of 4-digit rounding (0.7071), not of a non-rotation.
    if (!(std::fabs(norm - 1.0) <= 1e-3)) {
      r.context().error(r.child("orientation_wxyz"),
                        "not a unit quaternion (got norm " + format_number(norm) +
                            ", expected 1 within 0.001; identity is [1, 0, 0, 0])");
    } else {
      pose.orientation = Quat((*q)[0], (*q)[1], (*q)[2], (*q)[3]).normalized();
    }
  }
  if (aa) {
    auto axis = aa->vector3(plain("axis"), Need::kRequired, Range::closed(-1e6, 1e6));
    auto angle = aa->number("angle_deg", Need::kRequired, Range::closed(-360.0, 360.0), "deg");
    if (axis && axis->norm() < 1e-12) {
      r.context().error(aa->child("axis"), "zero axis (got [0, 0, 0], expected a non-zero direction)");
    } else if (axis && angle && !q) {
      pose.orientation = Quat(Eigen::AngleAxisd(*angle * M_PI / 180.0, axis->normalized()));
    }
    aa->finish();
  }
  r.finish();
}

void read_coupling(ObjectReader& r, CouplingConfig& c) {
  if (auto v = r.number("stiffness_N_m", Need::kOptional, Range::closed(1.0, 1e5), "N/m")) {
    c.stiffness_N_m = *v;
  }
  if (auto v = r.number("damping_Ns_m", Need::kOptional, Range::closed(0.0, 1e4), "N·s/m")) {
    c.damping_Ns_m = *v;
  }
  if (auto v = r.number("rot_stiffness_Nm_rad", Need::kOptional, Range::closed(1e-3, 1e3), "N·m/rad")) {
    c.rot_stiffness_Nm_rad = *v;
  }
  if (auto v = r.number("rot_damping_Nms_rad", Need::kOptional, Range::closed(0.0, 1e3), "N·m·s/rad")) {
    c.rot_damping_Nms_rad = *v;
  }
  r.finish();
}

std::vector<std::string> preset_names() {
  std::vector<std::string> out;
  for (const DevicePreset& p : device_presets()) out.emplace_back(p.name);
  return out;
}

void read_device(ObjectReader& r, DeviceConfig& d) {
  const bool has_preset = r.has("preset");
  if (auto p = r.string("preset", Need::kOptional, true, preset_names())) {
    const DevicePreset* preset = find_device_preset(*p);
    d.name = preset->name;
    d.max_force_N = preset->max_force_N;
  }
  if (auto s = r.string("name", Need::kOptional)) d.name = *s;
  else if (!has_preset) d.name = "custom";
  // Without a preset the rated force must be stated: a wrong limit is felt by the user.
  if (auto v = r.number("max_force_N", has_preset ? Need::kOptional : Need::kRequiredHere,
                        Range::closed(0.01, 100.0), "N")) {
    d.max_force_N = *v;
  }
  if (auto v = r.number("max_force_rate_N_s", Need::kOptional, Range::closed(0.1, 1e6), "N/s")) {
    d.max_force_rate_N_s = *v;
  }
  if (auto v = r.number("ramp_in_s", Need::kOptional, Range::closed(0.0, 60.0), "s")) d.ramp_in_s = *v;
  if (auto v = r.quantity(length("max_jump"), Need::kOptional, Range::closed(0.01 * kMm, 1.0))) d.max_jump_m = *v;
  r.finish();
}

void read_solver(ObjectReader& r, SolverConfig& s) {
  if (auto v = r.quantity(duration("dt"), Need::kOptional, Range::closed(kMinStep, 10e-3))) s.dt_s = *v;
  if (auto v = r.integer("nucleus_every", Need::kOptional, Range::closed(1, 10))) {
    s.nucleus_every = *v;
    // The particles' own step keeps to the range of dt.
    if (s.dt_s * s.nucleus_every > 10e-3 * (1.0 + 1e-12)) {
      const std::string at = r.pointer() + "/nucleus_every";
      r.context().error_located(at, at,
                                "nucleus_every " + std::to_string(s.nucleus_every) + " at dt " +
                                    format_number(s.dt_s / kMm) + " ms steps the particles at " +
                                    format_number(s.dt_s * s.nucleus_every / kMm) +
                                    " ms (expected at most 10 ms)");
    }
  }
  if (auto v = r.boolean("nucleus_pipelined", Need::kOptional)) s.nucleus_pipelined = *v;
  if (auto v = r.integer("max_iterations", Need::kOptional, Range::closed(1, 10000))) {
    s.max_iterations = *v;
  }
  if (auto v = r.number("tolerance", Need::kOptional, Range::closed(1e-10, 0.5))) s.tolerance = *v;
  if (auto v = r.boolean("sleep_enabled", Need::kOptional)) s.sleep_enabled = *v;
  if (auto v = r.quantity(speed("sleep_speed"), Need::kOptional, Range::closed(0.0, 1.0))) {
    s.sleep_speed_m_s = *v;
  }
  if (auto v = r.quantity(length("sleep_distance"), Need::kOptional, Range::closed(0.0, 0.1))) {
    s.sleep_distance_m = *v;
  }
  r.finish();
}

void read_removal(ObjectReader& r, RemovalRegionConfig& reg, const NucleusConfig& nucleus) {
  auto min = r.vector3(length("min"), Need::kRequired, kCoordinate);
  auto max = r.vector3(length("max"), Need::kRequired, kCoordinate);
  if (min && max && check_box(r, "min", "max", *min, *max)) {
    reg.min_m = *min;
    reg.max_m = *max;
    // A block outside the region would count as removed before the trainee touches it.
    for (std::size_t i = 0; i < nucleus.blocks.size(); ++i) {
      const ParticleBlockConfig& b = nucleus.blocks[i];
      if ((b.max_m.array() <= b.min_m.array()).any()) continue;  // already reported
      if ((b.min_m.array() >= reg.min_m.array()).all() && (b.max_m.array() <= reg.max_m.array()).all()) {
        continue;
      }
      r.context().error_located(r.pointer(), r.pointer(),
                                "removal region does not contain nucleus block " + std::to_string(i) +
                                    " (got region " + vec_text(reg.min_m, kMm, "mm") + " to " +
                                    vec_text(reg.max_m, kMm, "mm") + ", block " +
                                    vec_text(b.min_m, kMm, "mm") + " to " + vec_text(b.max_m, kMm, "mm") +
                                    ", expected the block inside the region)");
    }
  }
  r.finish();
}

void read_world(ObjectReader& r, WorldConfig& w, BoneModelConfig& bone,
                const std::string& scenario_path) {
  if (auto g = r.vector3(plain("gravity_m_s2", "m/s²"), Need::kOptional, Range::closed(-100.0, 100.0))) {
    w.gravity_m_s2 = *g;
  }
  if (auto o = r.object("ground", Need::kOptional)) read_ground(*o, w.ground);
  if (auto o = r.object("box", Need::kOptional)) read_box(*o, w.box);
  if (auto o = r.object("nucleus", Need::kOptional)) read_nucleus(*o, w.nucleus);
  if (auto o = r.object("instrument", Need::kOptional)) read_instrument(*o, w.instrument);
  read_instruments(r, w);
  if (auto o = r.object("instrument_start", Need::kOptional)) read_instrument_start(*o, w.instrument_start);
  if (auto o = r.object("coupling", Need::kOptional)) read_coupling(*o, w.coupling);
  if (auto o = r.object("device", Need::kOptional)) read_device(*o, w.device);
  if (auto o = r.object("solver", Need::kOptional)) read_solver(*o, w.solver);
  if (auto o = r.object("anatomy", Need::kOptional)) read_anatomy(*o, w.anatomy, bone, scenario_path);
  // Removal is what the nucleus is scored by, so a scene with a nucleus must say where it is.
  const bool nucleus_declared = r.has("nucleus");
  if (auto o = r.object("removal_region", nucleus_declared ? Need::kRequiredHere : Need::kOptional)) {
    read_removal(*o, w.removal, w.nucleus);
  }
  r.finish();
}

// ---------------------------------------------------------------------------------------------
// rubric

void read_rubric(ObjectReader& r, Rubric& rubric) {
  const std::vector<std::string>& metrics = known_metric_names();
  for (ObjectReader& tr : r.objects("terms", Need::kRequired, 1)) {
    RubricTerm t;
    if (auto s = tr.string("metric", Need::kRequired, true, metrics, "the metric to score", zone_metric_pattern())) {
      t.metric = *s;
    }
    if (auto v = tr.number("expert_mean", Need::kRequired, kMetricValue)) t.expert_mean = *v;
    if (auto v = tr.number("expert_sd", Need::kRequired, Range::closed(1e-9, 1e9))) {
      t.expert_sd = *v;
    }
    if (auto v = tr.boolean("higher_is_better", Need::kRequired)) t.higher_is_better = *v;
    if (auto v = tr.number("weight", Need::kOptional, Range::closed(0.0, 1000.0))) t.weight = *v;
    if (auto b = tr.boolean("safety", Need::kOptional)) t.safety = *b;
    if (auto v = tr.number("sd_floor", Need::kOptional, Range::closed(0.0, 1e9))) t.sd_floor = *v;
    tr.finish();
    rubric.terms.push_back(t);
  }
  // Every graded module states at least one safety gate (each safety metric passes on its own).
  for (ObjectReader& gr : r.objects("gates", Need::kRequired, 1)) {
    SafetyGate g;
    if (auto s = gr.string("metric", Need::kRequired, true, metrics, "the metric to limit", zone_metric_pattern())) {
      g.metric = *s;
    }
    if (auto v = gr.number("max", Need::kRequired, kMetricValue)) g.max = *v;
    gr.finish();
    rubric.gates.push_back(g);
  }
  // What "did the task" means; safety terms score only when it holds, so a rubric with any
  // must say.
  const bool has_safety_term =
      std::any_of(rubric.terms.begin(), rubric.terms.end(), [](const RubricTerm& t) { return t.safety; });
  if (auto o = r.object("task", has_safety_term ? Need::kRequiredHere : Need::kOptional)) {
    TaskRule task;
    if (auto s = o->string("metric", Need::kRequired, true, metrics, "the metric that shows the task was done",
                           zone_metric_pattern())) {
      task.metric = *s;
    }
    if (auto v = o->number("min", Need::kRequired, Range::any())) task.min = *v;
    o->finish();
    rubric.task = task;
  }
  if (!rubric.terms.empty()) {
    double total = 0.0;
    for (const RubricTerm& t : rubric.terms) total += t.weight;
    if (!(total > 0.0)) {
      r.context().error(r.child("terms"),
                        "all weights are zero (got total weight 0, expected a positive total)");
    }
  }
  if (auto v = r.number("pass_score", Need::kOptional, Range::closed(0.0, 100.0))) rubric.pass_score = *v;
  if (auto v = r.integer("consecutive_passes_to_master", Need::kOptional, Range::closed(1, 100))) {
    rubric.consecutive_passes_to_master = *v;
  }
  r.finish();
}

// ---------------------------------------------------------------------------------------------
// document

void read_document(ObjectReader& r, ScenarioModel& m) {
  // "$schema" lets an editor find scenario.schema.json; it has no meaning for the loader.
  r.string("$schema", Need::kOptional);
  if (auto v = r.integer("format_version", Need::kRequired, Range::any(), "the format version, 1")) {
    if (*v != 1) {
      r.context().error(r.child("format_version"),
                        "unsupported format version (got " + std::to_string(*v) + ", expected 1)");
    }
    m.format_version = *v;
  }
  if (auto s = r.string("id", Need::kRequired, true, {}, "the module id, e.g. \"box-warmup\"")) {
    static const std::regex kId("[a-z0-9][a-z0-9_-]*");
    if (!std::regex_match(*s, kId) || s->size() > 64) {
      r.context().error(r.child("id"),
                        "bad module id (got " + in_quotes(s->substr(0, 64)) +
                            ", expected up to 64 lower-case letters, digits, '-' or '_', "
                            "starting with a letter or digit)");
    }
    m.id = *s;
  }
  if (auto s = r.string("title", Need::kRequired, true, {}, "the title shown to trainees")) m.title = *s;
  if (auto s = r.string("goal", Need::kRequired, true, {}, "the learning goal in plain words")) m.goal = *s;
  if (auto s = r.string("curriculum", Need::kOptional, true, {},
                        "the curriculum id, e.g. \"acdr-scooping\"")) {
    m.curriculum = *s;
  }
  if (auto v = r.integer("module_order", Need::kOptional, Range::closed(0, 10000))) m.module_order = *v;
  if (auto v = r.number("time_limit_s", Need::kOptional, Range::closed(0.0, 86400.0), "s")) {
    m.time_limit_s = *v;
  }
  if (auto o = r.object("world", Need::kRequired)) read_world(*o, m.world, m.bone, m.path);
  if (auto o = r.object("rubric", Need::kRequired)) read_rubric(*o, m.rubric);
  // A bone metric exists only where the bone is modelled: a rubric without it would fail
  // its gate ("not measured") on every attempt.
  if (!m.bone.enabled) {
    auto check = [&](const std::string& metric, const std::string& pointer) {
      if (!is_bone_metric_name(metric)) return;
      r.context().error(pointer, "bone metric without a bone model (got " + in_quotes(metric) +
                                     ", expected world.anatomy.bone to be present and enabled, "
                                     "or a metric that is not a bone stress)");
    };
    for (std::size_t i = 0; i < m.rubric.terms.size(); ++i)
      check(m.rubric.terms[i].metric, "/rubric/terms/" + std::to_string(i) + "/metric");
    for (std::size_t i = 0; i < m.rubric.gates.size(); ++i)
      check(m.rubric.gates[i].metric, "/rubric/gates/" + std::to_string(i) + "/metric");
  }
  r.finish();
}

// ---------------------------------------------------------------------------------------------
// budget

/// The first of `pointers` present in `doc` (the spelling the file used), else the last.
std::string present(const json& doc, const std::vector<std::string>& pointers) {
  for (const std::string& p : pointers) {
    if (doc.contains(json::json_pointer(p))) return p;
  }
  return pointers.back();
}

/// Refuses a scenario whose estimated cost exceeds the budget (scenario_cost.hpp), each
/// figure at the key that drives it. Run only on a file without other errors.
void check_budget(LoadContext& ctx, const json& doc, const ScenarioModel& m) {
  using B = ScenarioBudget;
  const ScenarioCost c = estimate_cost(m);
  const WorldConfig& w = m.world;
  const std::string spacing = format_number(w.nucleus.spacing_m / kMm) + " mm";
  const std::size_t before = ctx.error_count();
  if (c.particles > B::kParticles) {
    ctx.error("/world/nucleus/blocks",
              "too many particles (got about " + format_number(std::round(c.particles)) + " at spacing " +
                  spacing + ", expected at most " + format_number(B::kParticles) +
                  "; use a larger spacing or smaller blocks)");
  }
  if (c.bonds > B::kBonds) {
    ctx.error(present(doc, {"/world/nucleus/bond_radius_factor", "/world/nucleus/blocks"}),
              "too many bonds (got about " + format_number(std::round(c.bonds)) + ": " +
                  format_number(std::round(c.particles)) + " particles with " +
                  std::to_string(lattice_neighbours_within(w.nucleus.bond_radius_factor)) +
                  " lattice neighbours each within " + format_number(w.nucleus.bond_radius_factor) +
                  " spacings, expected at most " + format_number(B::kBonds) +
                  "; use a smaller bond_radius_factor or fewer particles)");
  }
  if (c.grid_cells > B::kGridCells && c.vertebra_samples > 0.5 * c.grid_cells) {
    ctx.error(present(doc, {"/world/anatomy/morphometry/mesh_spacing_mm", "/world/anatomy/morphometry/mesh_spacing_m",
                            "/world/anatomy/morphometry", "/world/anatomy"}),
              "distance grids too large (got about " + format_number(std::round(c.grid_cells)) +
                  " samples, " + format_number(std::round(c.vertebra_samples)) +
                  " of them to mesh the vertebrae at mesh_spacing " +
                  format_number(w.anatomy.segment.mesh_spacing_m / kMm) + " mm, expected at most " +
                  format_number(B::kGridCells) + "; use a coarser mesh_spacing)");
  } else if (c.grid_cells > B::kGridCells) {
    const AnatomyConfig& a = w.anatomy;
    ctx.error(present(doc, {"/world/anatomy/sdf/spacing_mm", "/world/anatomy/sdf/spacing_m",
                            "/world/anatomy/sdf/zone_spacing_mm", "/world/anatomy/sdf/zone_spacing_m",
                            "/world/anatomy/sdf", "/world/anatomy"}),
              "distance grids too large (got about " + format_number(std::round(c.grid_cells)) +
                  " samples at spacing " + format_number(a.sdf.spacing_m / kMm) + " mm and zone_spacing " +
                  format_number(a.zone_sdf_spacing_m / kMm) + " mm over the grid region and a margin of " +
                  format_number(a.sdf.margin_m / kMm) + " mm, expected at most " + format_number(B::kGridCells) +
                  "; use a coarser spacing, a smaller margin or a smaller region)");
  }
  if (c.recording_frames > B::kRecordingFrames) {
    ctx.error(present(doc, {"/time_limit_s"}),
              "recording too long (got " + format_number(c.recording_frames) + " frames: " +
                  format_number(m.time_limit_s) + " s at a " + format_number(w.solver.dt_s / kMm) +
                  " ms step, expected at most " + format_number(B::kRecordingFrames) +
                  "; shorten time_limit_s or lengthen the step)");
  }
  // The memory of all together, when no single figure is already over.
  if (ctx.error_count() == before && c.bytes > B::kBytes) {
    ctx.error("/world", "estimated memory too large (got " + format_bytes(c.bytes) + " for " +
                            format_number(std::round(c.particles)) + " particles, " +
                            format_number(std::round(c.bonds)) + " bonds, " +
                            format_number(std::round(c.grid_cells)) + " grid samples and " +
                            format_number(c.recording_frames) + " frames, expected at most " +
                            format_bytes(B::kBytes) + ")");
  }
}

/// nlohmann's messages start "[json.exception.parse_error.101] parse error at line 3,
/// column 5: "; keep what follows (our own prefix gives the position).
std::string parse_detail(const std::string& what) {
  std::string detail = what;
  const std::size_t bracket = detail.find("] ");
  if (detail.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos) {
    detail = detail.substr(bracket + 2);
  }
  if (detail.rfind("parse error", 0) == 0) {
    const std::size_t colon = detail.find(": ");
    if (colon != std::string::npos) detail = detail.substr(colon + 2);
  }
  return detail;
}

}  // namespace

LoadResult load_scenario_text(const std::string& text, const std::string& path_for_messages) {
  return load_scenario_text(text, path_for_messages, nullptr);
}

LoadResult load_scenario_text(const std::string& text, const std::string& path,
                              KeyRegistry* registry) {
  LoadResult result;
  auto fail = [&](int line, int column, std::string message) {
    result.errors.push_back({path, line, column, "", std::move(message)});
    return result;
  };
  if (text.size() > kMaxScenarioFileBytes) {
    return fail(1, 1, "file too large (got " + std::to_string(text.size()) + " bytes, expected at most " +
                          std::to_string(kMaxScenarioFileBytes) + ")");
  }

  // Parse. nlohmann's parser is iterative, so deep nesting cannot exhaust the stack.
  json doc;
  try {
    doc = json::parse(text, nullptr, true, false);
  } catch (const json::parse_error& e) {
    const JsonPositionIndex lines = JsonPositionIndex::lines_only(text);
    std::size_t offset = e.byte == 0 ? 0 : e.byte - 1;
    const bool at_end = e.byte >= text.size();
    if (at_end) {
      // Point just after the last thing written, not at an empty last line.
      const std::size_t last = text.find_last_not_of(" \t\r\n");
      offset = last == std::string::npos ? 0 : last + 1;
    }
    const TextPosition at = lines.position_of_offset(std::min(offset, text.size()));
    std::string message = "malformed JSON at column " + std::to_string(at.column) + ": " +
                          parse_detail(e.what());
    if (at_end) message = "the file ends before the JSON is complete (truncated?): " + parse_detail(e.what());
    return fail(at.line, at.column, message);
  } catch (const json::exception& e) {
    // Number overflow (e.g. 1e400) is reported without a position; find the literal.
    std::string what = e.what();
    const JsonPositionIndex lines = JsonPositionIndex::lines_only(text);
    TextPosition at{1, 1};
    const std::size_t q1 = what.find('\''), q2 = what.rfind('\'');
    if (q1 != std::string::npos && q2 > q1) {
      const std::size_t found = text.find(what.substr(q1 + 1, q2 - q1 - 1));
      if (found != std::string::npos) at = lines.position_of_offset(found);
    }
    return fail(at.line, at.column, "malformed JSON: " + parse_detail(what) +
                                        " (expected a number within double precision range)");
  }

  std::vector<DuplicateKey> duplicates;
  const JsonPositionIndex index(text, &duplicates);
  LoadContext ctx(path, index, registry);
  for (const DuplicateKey& d : duplicates) {
    ctx.error_located(d.json_path, d.json_path,
                      "duplicate key (first at line " + std::to_string(d.first.line) +
                          "; expected each key once, the later value would silently win)");
    ctx.errors().back().line = d.second.line;
    ctx.errors().back().column = d.second.column;
  }

  auto model = std::make_shared<ScenarioModel>();
  model->path = path;
  model->hash = fnv1a64_hex(text);
  ObjectReader root(ctx, doc, "", "");
  if (root.valid()) read_document(root, *model);
  // What it will cost, once every number is known to be in range.
  if (ctx.error_count() == 0) check_budget(ctx, doc, *model);

  result.errors = std::move(ctx.errors());
  std::stable_sort(result.errors.begin(), result.errors.end(),
                   [](const ScenarioError& a, const ScenarioError& b) { return a.line < b.line; });
  if (result.errors.empty()) result.model = std::move(model);
  return result;
}

LoadResult load_scenario_file(const std::string& path) {
  // Only a regular file, opened without blocking and capped (engine/core/input_file.hpp).
  std::string error;
  const std::optional<std::string> text =
      read_input_file(path, kMaxScenarioFileBytes, "a scenario file", &error);
  if (!text) {
    LoadResult r;
    r.errors.push_back({path, 0, 0, "", error});
    return r;
  }
  return load_scenario_text(*text, path, nullptr);
}

}  // namespace acdr

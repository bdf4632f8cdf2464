// `acdr render`: build the scenario's world and draw it at t = 0, or the bone's stress under a
// given load or a recorded attempt's loads at a given time.
#include "cli/render_command.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <ostream>
#include <sstream>

#include "app/bone_metrics_replay.hpp"
#include "assessment/recording.hpp"
#include "db/attempt_store.hpp"
#include "scenarios/scenario_loader.hpp"
#include "ui/anatomy_view.hpp"
#include "ui/bone_stress_view.hpp"
#include "ui/offscreen_render.hpp"
#include "ui/scene_snapshot.hpp"

namespace acdr {
namespace {

/// "x,y,z,fx,fy,fz" in mm and N; false with `error` set otherwise.
bool parse_load(const std::string& text, double radius_mm, BoneLoadPoint* load, std::string* error) {
  double v[6];
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &v[4],
                  &v[5], &tail) != 6) {
    *error = "--stress-load: got '" + text + "', expected x,y,z,fx,fy,fz (mm, N), e.g. 0,2.95,1,0,-20,0";
    return false;
  }
  for (double x : v)
    if (!std::isfinite(x)) {
      *error = "--stress-load: got '" + text + "', expected finite numbers";
      return false;
    }
  load->point_m = Eigen::Vector3f(static_cast<float>(v[0] * 1e-3), static_cast<float>(v[1] * 1e-3),
                                  static_cast<float>(v[2] * 1e-3));
  load->force_N = Eigen::Vector3f(static_cast<float>(v[3]), static_cast<float>(v[4]),
                                  static_cast<float>(v[5]));
  load->radius_m = static_cast<float>(radius_mm * 1e-3);
  return true;
}

/// The recording of a file or a stored attempt.
std::optional<AttemptRecording> read_recording(const RenderOptions& o, std::string* error) {
  std::vector<std::uint8_t> bytes;
  std::string where;
  if (!o.recording.empty()) {
    std::ifstream in(o.recording, std::ios::binary);
    if (!in) {
      *error = o.recording + ": cannot open the recording";
      return std::nullopt;
    }
    bytes.assign(std::istreambuf_iterator<char>(in), {});
    where = o.recording;
  } else {
    const std::string db_path = o.db.empty() ? default_database_path() : o.db;
    OpenOptions open;
    open.create = false;
    auto db = open_store(db_path, open);
    if (!db) {
      *error = db.error().message;
      return std::nullopt;
    }
    auto full = load_attempt(db.value(), o.attempt, {true, false, true});
    if (!full) {
      *error = full.error().message;
      return std::nullopt;
    }
    if (!full.value() || !full.value()->recording) {
      *error = db_path + ": attempt " + std::to_string(o.attempt) + " has no recording";
      return std::nullopt;
    }
    bytes = full.value()->recording->bytes;
    where = db_path + ": attempt " + std::to_string(o.attempt);
  }
  std::string why;
  auto r = decode_recording(bytes, &why);
  if (!r) *error = where + ": " + why;
  return r;
}

int render_stress(const RenderOptions& o, const ScenarioModel& scenario, std::ostream& out,
                  std::ostream& err) {
  if (!scenario.bone.enabled) {
    err << o.scenario << ": the scenario does not model the bone (world.anatomy.bone); "
        << "--stress needs it\n";
    return 2;
  }
  std::vector<BoneLoadPoint> loads;
  std::string caption, error;
  BoneMetricsReplay replay;
  const BoneSegment* bone = replay.bone(scenario, &error);
  if (!bone) {
    err << o.scenario << ": bone model: " << error << "\n";
    return 2;
  }
  if (!o.stress_loads.empty()) {
    for (const std::string& text : o.stress_loads) {
      BoneLoadPoint p;
      if (!parse_load(text, o.stress_radius_mm, &p, &error)) {
        err << error << "\n";
        return 2;
      }
      // On the vertebra whose surface is nearer.
      Vec3 closest;
      double d4 = 0.0, d5 = 0.0;
      const Vec3 x = p.point_m.cast<double>();
      const bool on4 = bone->vertebra(0).surface().closest_face(x, 0.05, &closest, &d4) >= 0;
      const bool on5 = bone->vertebra(1).surface().closest_face(x, 0.05, &closest, &d5) >= 0;
      p.vertebra = (on4 && (!on5 || d4 < d5)) ? 0 : 1;
      loads.push_back(p);
    }
    caption = "Given load" + std::string(loads.size() > 1 ? "s" : "");
  } else {
    auto record = read_recording(o, &error);
    if (!record) {
      err << error << "\n";
      return 2;
    }
    if (record->bone_loads.empty()) {
      err << "the recording has no bone load samples (recorded without the bone model)\n";
      return 2;
    }
    double at = o.at_s;
    if (at < 0.0) {
      // The moment of peak bone load.
      double peak = -1.0;
      for (const BoneLoadRecord& r : record->bone_loads) {
        double sum = 0.0;
        for (const BoneLoadPoint& p : r.points) sum += p.force_N.cast<double>().norm();
        if (sum > peak) peak = sum, at = r.t_s;
      }
    }
    const BoneLoadRecord* nearest = &record->bone_loads.front();
    for (const BoneLoadRecord& r : record->bone_loads)
      if (std::abs(r.t_s - at) < std::abs(nearest->t_s - at)) nearest = &r;
    loads = nearest->points;
    char text[160];
    std::snprintf(text, sizeof text, "Recorded attempt at t = %.2f s%s", nearest->t_s,
                  o.at_s < 0.0 ? " (peak bone load)" : "");
    caption = text;
  }
  BoneSegmentScratch scratch;
  scratch.nodal_fields = true;
  const BoneSampleResult result = bone->solve(0.0, loads, scratch);
  if (!result.solved[0] && !result.solved[1]) {
    err << "no vertebra is loaded (the loads add up to less than "
        << scenario.bone.min_load_N << " N, or miss the bone)\n";
    return 2;
  }
  const BoneStressView view =
      bone_stress_view(*bone, scratch, result, loads,
                       static_cast<float>(o.width) / static_cast<float>(o.height),
                       o.stress_max_MPa * 1e6);
  if (!render_bone_stress_png(view, caption, o.width, o.height, o.png, &error)) {
    err << o.png << ": " << error << "\n";
    return 2;
  }
  char line[200];
  std::snprintf(line, sizeof line,
                "wrote %s (%dx%d): %s peak von Mises %.3f MPa, largest displacement %.3f um\n",
                o.png.c_str(), o.width, o.height, view.vertebra == 0 ? "C4" : "C5",
                view.peak_Pa * 1e-6, view.max_displacement_m * 1e6);
  out << line;
  return 0;
}

}  // namespace

int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err) {
  const LoadResult loaded = load_scenario_file(options.scenario);
  if (!loaded.ok()) {
    err << to_string(loaded.errors);
    return 2;
  }
  if (!options.stress_loads.empty() || !options.recording.empty() || options.attempt != 0)
    return render_stress(options, *loaded.model, out, err);
  AnatomyView view;
  if (!parse_anatomy_view(options.view, &view)) {
    err << "--view: got '" << options.view << "', expected surgeon, anterior or lateral\n";
    return 2;
  }
  const World world(loaded.model->world);
  const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height);
  SceneStyle style;
  if (view != AnatomyView::kSurgeon) style.draw_instrument = style.draw_walls = false;  // the anatomy alone
  SnapshotOptions drawing;
  drawing.drawing = options.beads ? MaterialDrawing::kBeads : MaterialDrawing::kSurfaces;
  RenderScene scene = snapshot_world(world, aspect, style, drawing);
  if (view != AnatomyView::kSurgeon) {
    if (!world.anatomy()) {
      err << options.scenario << ": --view " << options.view
          << " needs an anatomical scene (world.anatomy)\n";
      return 2;
    }
    scene.camera = anatomy_camera(*world.anatomy(), view, aspect);
    scene.ground.visible = false;  // the table would stand as a wall across these views
  }
  std::string error;
  const bool written =
      options.labels && view != AnatomyView::kSurgeon
          ? render_labelled_png(scene, anatomy_labels(world, view),
                                options.view == "anterior" ? "C4-C5 from the front (patient's left on the right)"
                                                           : "C4-C5 from the patient's left (anterior on the left)",
                                options.width, options.height, options.png, &error)
          : render_to_png(scene, options.width, options.height, options.png, &error);
  if (!written) {
    err << options.png << ": " << error << "\n";
    return 2;
  }
  out << "wrote " << options.png << " (" << options.width << "x" << options.height << ")\n";
  return 0;
}

}  // namespace acdr

// Tests of ui/trainee_hud: the HUD's model from a live view (alerts from the live state and
// from recent events), a trainee-view frame drawn offscreen over the 3D scene with the
// instrument, the material and the HUD's warning colours present, and the score screen.
#include "ui/trainee_hud.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include "assessment/scoring.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/ui/image_probe.hpp"
#include "tests/ui/test_record.hpp"
#include "tests/ui/text_fit_probe.hpp"
#include "ui/imgui_offscreen.hpp"
#include "ui/png_writer.hpp"
#include "ui/render_camera.hpp"
#include "ui/scene_snapshot.hpp"

namespace acdr {
namespace {

using test::Image;
using test::Rgb;

std::shared_ptr<const ScenarioModel> small_box() {
  LoadResult loaded = load_scenario_file(test::kSceneData + "small_box.json");
  EXPECT_TRUE(loaded.ok()) << to_string(loaded.errors);
  return loaded.model;
}

bool is_amber(const Rgb& c) { return c.r > 200 && c.g > 130 && c.g < 200 && c.b < 90; }
bool is_alert_red(const Rgb& c) { return c.r > 190 && c.g < 100 && c.b < 100; }

TEST(TraineeHud, AlertsComeFromLiveStateAndRecentEvents) {
  const auto scenario = small_box();
  World world(scenario->world);
  LiveView view;
  capture_world_state(world, view.state);
  view.state.frame.t_s = 10.0;
  HapticLoopStats loop;
  loop.rate_hz = 600;
  loop.target_rate_hz = 1000;

  HudModel calm = make_hud_model(*scenario, world.summary(), view, loop, "mouse");
  EXPECT_TRUE(calm.alerts.empty());
  EXPECT_EQ(calm.title, scenario->title);
  EXPECT_DOUBLE_EQ(calm.device_max_N, 3.3);

  // Shaft above its warning moment, the device silent, a clamp 1 s ago, a rejection 5 s ago.
  view.state.frame.bending_moment_Nm = 1.2 * world.summary().warning_moment_Nm;
  view.sample.stale = true;
  view.events.push_back(Event{5.0, EventKind::kInputRejected, 0.05, "pose jump"});
  view.events.push_back(Event{9.0, EventKind::kForceClamped, 4.2, "force above device maximum"});
  const HudModel hud = make_hud_model(*scenario, world.summary(), view, loop, "mouse");
  EXPECT_NEAR(hud.realtime_factor, 0.0, 1e-12);  // too few ticks to say
  ASSERT_EQ(hud.alerts.size(), 3u);
  EXPECT_EQ(hud.alerts[0].level, AlertLevel::kDanger);  // most severe first
  EXPECT_NE(hud.alerts[0].text.find("silent"), std::string::npos);
  EXPECT_NE(hud.alerts[1].text.find("overload"), std::string::npos);
  EXPECT_NE(hud.alerts[2].text.find("4.2 N"), std::string::npos);  // the recent clamp only

  // The real-time factor, once the loop has run a while: 600 of 1000 Hz is slow motion.
  loop.ticks = 5000;
  EXPECT_NEAR(make_hud_model(*scenario, world.summary(), view, loop, "mouse").realtime_factor,
              0.6, 1e-12);
  EXPECT_TRUE(is_slow_motion(0.6));
  EXPECT_NE(realtime_text(0.6).find("0.60x real time: slow motion"), std::string::npos);
  EXPECT_NE(realtime_text(0.6).find("coarser lattice"), std::string::npos);
  EXPECT_FALSE(is_slow_motion(0.97));
  EXPECT_EQ(realtime_text(1.02), "Real time (1.00x)");
  EXPECT_EQ(realtime_text(0.0), "");

  // Above yield it is a danger.
  view.sample.stale = false;
  view.state.frame.bending_moment_Nm = 1.1 * world.summary().yield_moment_Nm;
  const HudModel bent = make_hud_model(*scenario, world.summary(), view, loop, "mouse");
  ASSERT_FALSE(bent.alerts.empty());
  EXPECT_EQ(bent.alerts[0].level, AlertLevel::kDanger);
  EXPECT_NE(bent.alerts[0].text.find("yield"), std::string::npos);
}

TEST(TraineeHud, FrameOffscreenShowsInstrumentMaterialHudAndWarningColours) {
  const auto scenario = small_box();
  World world(scenario->world);
  DeviceSample s;
  s.pose = scenario->world.instrument_start;
  for (int i = 0; i < 30; ++i) world.step(s);
  LiveView view;
  capture_world_state(world, view.state);
  view.state.frame.bending_moment_Nm = 1.1 * world.summary().yield_moment_Nm;
  view.sample.stale = true;

  const int w = 1000, h = 640;
  const RenderScene scene = snapshot_state(world, view.state, float(w) / h);
  const HudModel hud =
      make_hud_model(*scenario, world.summary(), view, HapticLoopStats{}, "udp:7000");
  std::string error;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  ASSERT_TRUE(ui) << error;
  Image im{w, h, {}};
  ASSERT_TRUE(ui->render(&scene, [&] { draw_trainee_hud(hud, ImVec2(w, h), nullptr); }, &im.rgb,
                         &error))
      << error;

  // The instrument's blade (steel) and the nucleus (yellow) where the camera puts them.
  const Collider* blade = nullptr;
  for (const Collider& c : view.state.instrument)
    if (c.kind == ColliderKind::kBox) blade = &c;
  ASSERT_NE(blade, nullptr);
  const auto blade_px =
      project_to_pixel(scene.camera, w, h, blade->pose.position.cast<float>());
  ASSERT_TRUE(blade_px);
  EXPECT_GT(im.fraction_in_window(*blade_px, 2, test::is_steel), 0.5)
      << "blade at " << blade_px->transpose();
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : view.state.positions) centroid += p;
  centroid /= static_cast<float>(view.state.positions.size());
  centroid.z() = view.state.positions.back().z();  // the top layer, seen from above
  const auto nucleus_px = project_to_pixel(scene.camera, w, h, centroid);
  ASSERT_TRUE(nucleus_px);
  EXPECT_GT(im.fraction_in_window(*nucleus_px, 3, test::is_nucleus_yellow), 0.5);

  // The HUD: text in the status window (top right), and the alert colours: red for the
  // silent device and the bent shaft, amber marks on the gauges.
  int text = 0;
  for (int y = 40; y < 260; ++y)
    for (int x = w - 330; x < w - 12; ++x) {
      const Rgb c = im.at(x, y);
      text += c.r > 170 && c.g > 170 && c.b > 170;
    }
  EXPECT_GT(text, 300);
  EXPECT_GT(im.fraction(is_alert_red), 0.0005);
  EXPECT_GT(im.fraction(is_amber), 0.00005);
}

// The anatomical module: a danger zone the instrument comes near turns its warning colour in
// the 3D view, and the HUD names it.
TEST(TraineeHud, ZoneTurnsItsWarningColourAndTheHudNamesIt) {
  LoadResult loaded =
      load_scenario_file(std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/02_c4c5_healthy.json");
  ASSERT_TRUE(loaded.ok()) << to_string(loaded.errors);
  World world(loaded.model->world);
  ASSERT_NE(world.anatomy(), nullptr);
  const auto& zones = world.anatomy()->zones();
  std::size_t artery = zones.size();
  for (std::size_t i = 0; i < zones.size(); ++i)
    if (zones[i].name.find("artery") != std::string::npos) artery = std::min(artery, i);
  ASSERT_LT(artery, zones.size());

  LiveView view;
  capture_world_state(world, view.state);
  Frame& f = view.state.frame;
  ASSERT_GT(f.zone_count, static_cast<int>(artery));
  f.zones[artery].warning = true;
  f.zones[artery].distance_m = 1.5e-3f;

  const SceneStyle style;
  const int w = 1000, h = 640;
  const RenderScene scene = snapshot_state(world, view.state, float(w) / h, style);
  int warned = 0;
  for (const RenderMesh& m : scene.meshes) warned += m.rgba == style.zone_warning;
  EXPECT_EQ(warned, 1);

  const HudModel hud = make_hud_model(*loaded.model, world.summary(), view, HapticLoopStats{},
                                      "mouse");
  ASSERT_FALSE(hud.alerts.empty());
  EXPECT_EQ(hud.alerts[0].level, AlertLevel::kWarning);
  // By its human name ("left vertebral artery"), not its id.
  EXPECT_NE(hud.alerts[0].text.find(zone_display_name(zones[artery].name)), std::string::npos)
      << hud.alerts[0].text;
  EXPECT_EQ(hud.alerts[0].text.find('_'), std::string::npos) << hud.alerts[0].text;
  EXPECT_NE(hud.alerts[0].text.find("1.5 mm"), std::string::npos) << hud.alerts[0].text;

  // Inside the zone with its entry, its force events and a never-event: one line, its latest
  // state; three clamps: one line.
  f.zones[artery].warning = false;
  f.zones[artery].inside = true;
  f.t_s = 10.0;
  const int z = static_cast<int>(artery);
  LiveView busy = view;
  busy.events = {Event{9.0, EventKind::kZoneWarning, 0.002, zones[artery].name, z},
                 Event{9.2, EventKind::kZoneEntry, 0.0, zones[artery].name, z},
                 Event{9.2, EventKind::kNeverEvent, 0.0, zones[artery].name, z},
                 Event{9.3, EventKind::kZoneForce, 1.4, zones[artery].name, z},
                 Event{9.4, EventKind::kForceClamped, 3.6, "", -1},
                 Event{9.5, EventKind::kForceClamped, 3.9, "", -1},
                 Event{9.6, EventKind::kForceClamped, 4.3, "", -1}};
  const HudModel inside = make_hud_model(*loaded.model, world.summary(), busy, HapticLoopStats{},
                                         "mouse");
  ASSERT_EQ(inside.alerts.size(), 2u);
  EXPECT_EQ(inside.alerts[0].level, AlertLevel::kDanger);
  const std::string& line = inside.alerts[0].text;
  EXPECT_NE(line.find("Inside the " + zone_display_name(zones[artery].name)), std::string::npos)
      << line;
  EXPECT_NE(line.find("1.40 N"), std::string::npos) << line;
  EXPECT_NE(line.find("never-event"), std::string::npos) << line;
  EXPECT_NE(inside.alerts[1].text.find("4.3 N"), std::string::npos);  // the newest clamp

  std::string error;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  ASSERT_TRUE(ui) << error;
  Image im{w, h, {}};
  ASSERT_TRUE(ui->render(&scene, [&] { draw_trainee_hud(hud, ImVec2(w, h), nullptr); }, &im.rgb,
                         &error));
  // The warned artery is amber on screen where its centre projects; the instrument is steel.
  const Vec3 mid = 0.5 * (zones[artery].a_m + zones[artery].b_m);
  const auto px = project_to_pixel(scene.camera, w, h, mid.cast<float>());
  ASSERT_TRUE(px);
  EXPECT_GT(im.fraction_in_window(*px, 3, [](const Rgb& c) {
    return c.r > 180 && c.g > 90 && c.g < 200 && c.b < 90;
  }), 0.4) << "artery at " << px->transpose();
  EXPECT_GT(im.fraction(test::is_steel), 0.005);
}

AttemptRun failing_run() {
  AttemptRun run;
  run.end = AttemptEnd::kTimeLimit;
  run.score.score = 31.0;
  run.score.passed = false;
  run.score.terms = {{"nucleus_removed_fraction", 0.05, 30.0}, {"peak_instrument_force_N", 1.0, 60.0}};
  run.score.gates = {{"overload_events", 2.0, 0.0, false}};
  run.score.reasons = {"composite score 31.0 is below the pass score 50.0"};
  run.metrics.set("nucleus_removed_fraction", 0.05);
  run.metrics.set("peak_instrument_force_N", 1.0);
  run.metrics.set("overload_events", 2.0);
  Frame last;
  last.t_s = 60.0;
  run.record.frames.push_back(last);
  return run;
}

TEST(TraineeHud, ScoreScreenSaysWhatToImprove) {
  const auto scenario = small_box();
  const ScoreScreenModel s = make_score_screen(*scenario, failing_run(), "Stored as attempt 3");
  EXPECT_FALSE(s.passed);
  EXPECT_EQ(s.end_reason, "time limit");
  EXPECT_DOUBLE_EQ(s.duration_s, 60.0);
  ASSERT_EQ(s.rows.size(), 3u);  // two scored metrics, then the gate
  EXPECT_FALSE(s.rows[0].good);
  EXPECT_NE(benchmark_text(s.rows[0]).find("0.15"), std::string::npos)
      << benchmark_text(s.rows[0]);
  EXPECT_TRUE(s.rows[1].good);
  EXPECT_EQ(s.rows[2].judgement, MetricJudgement::kGated);
  EXPECT_FALSE(s.rows[2].good);
  // Improvements: the weak metric with its target, the failed gate, the reason.
  ASSERT_EQ(s.improvements.size(), 3u);
  EXPECT_NE(s.improvements[0].find("aim higher"), std::string::npos) << s.improvements[0];
  EXPECT_NE(s.improvements[1].find("at or below 0"), std::string::npos) << s.improvements[1];

  const int w = 900, h = 600;
  std::string error;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  ASSERT_TRUE(ui) << error;
  Image im{w, h, {}};
  ASSERT_TRUE(ui->render(nullptr, [&] { draw_score_screen(s, ImVec2(w, h)); }, &im.rgb, &error));
  EXPECT_GT(im.fraction(is_alert_red), 0.0005);  // NOT PASSED, FAILED
}

// The anatomical module's score screen: what happened in the zones, by the zone's name, with
// the time and the force; the safety terms marked; the scale explained.
TEST(TraineeHud, ScoreScreenNamesTheZoneAndExplainsTheScale) {
  LoadResult loaded =
      load_scenario_file(std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/02_c4c5_healthy.json");
  ASSERT_TRUE(loaded.ok()) << to_string(loaded.errors);
  AttemptRun run;
  run.end = AttemptEnd::kInputEnded;
  run.record.summary.zones = {{"vertebral_artery_left", 3e-3, 0.5, true},
                              {"spinal_cord_pll", 1.5e-3, 0.5, true}};
  Metrics& m = run.metrics;
  m.set("nucleus_removed_fraction", 0.3);
  m.set("peak_bending_moment_Nm", 0.05);
  m.set("zone_dwell_s", 2.0);
  m.set("zone_impulse_Ns", 1.1);
  m.set("protected_removed_mm3", 3.0);
  m.set("overload_events", 0);
  m.set("zone_entries", 1);
  m.set("zone_over_limit_events", 1);
  m.set("never_events", 1);
  m.set("zone.spinal_cord_pll.dwell_s", 2.0);
  m.set("zone.spinal_cord_pll.inside_s", 1.7);
  m.set("zone.spinal_cord_pll.peak_force_N", 1.4);
  m.set("zone.spinal_cord_pll.entries", 1);
  m.set("zone.spinal_cord_pll.never_event", 1);
  run.score = score_attempt(run.metrics, loaded.model->rubric);
  Frame last;
  last.t_s = 35.6;
  run.record.frames.push_back(last);
  const ScoreScreenModel s = make_score_screen(*loaded.model, run, "Stored as attempt 7");
  ASSERT_EQ(s.zone_findings.size(), 1u);
  EXPECT_EQ(s.zone_findings[0].rfind("Entered the spinal cord / PLL zone for 1.7 s at up to 1.4 N", 0), 0u)
      << s.zone_findings[0];
  int safety_rows = 0;
  for (const ScoreTableRow& r : s.rows) safety_rows += r.safety;
  EXPECT_EQ(safety_rows, 5);  // moment, time and force-time near zones, annulus, endplate stress
  ASSERT_GE(s.scale.size(), 4u);
  EXPECT_NE(s.scale[0].find("50 = the experts' mean"), std::string::npos) << s.scale[0];
  EXPECT_NE(s.scale[0].find("10 points"), std::string::npos) << s.scale[0];
  EXPECT_NE(s.scale[1].find("\"Higher is better\""), std::string::npos) << s.scale[1];
  EXPECT_NE(s.scale[3].find("only by doing the task"), std::string::npos) << s.scale[3];

  const int w = 1280, h = 800;
  std::string error;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  ASSERT_TRUE(ui) << error;
  Image im{w, h, {}};
  std::vector<std::string> overflows;
  ASSERT_TRUE(ui->render(
      nullptr,
      [&] {
        draw_score_screen(s, ImVec2(w, h));
        overflows = test::text_overflows(ImVec2(w, h));
      },
      &im.rgb, &error));
  EXPECT_GT(im.fraction(is_alert_red), 0.0005);
  for (const std::string& o : overflows) ADD_FAILURE() << o;  // every label fits at 1280 x 800
  EXPECT_TRUE(write_png_rgb("score_screen_1280x800.png", w, h, im.rgb, &error)) << error;
  if (const char* out = std::getenv("ACDR_TEST_SCREENSHOTS")) {
    EXPECT_TRUE(write_png_rgb(std::string(out) + "/score_screen_zone.png", w, h, im.rgb, &error)) << error;
  }
}

// The live HUD of module 02 at 1280 x 800 in mouse mode with every part showing at once (a
// zone entered with a never-event and its force, another zone close, repeated clamps, the
// shaft over its warning, slow motion): no text is cut off, no window covers the goal, zones
// read by their names. The picture is kept as trainee_hud_1280x800.png.
// Module 02's tray: the HUD says which instrument is in hand (the first until the hand takes
// another) and announces an exchange for a moment, as information, not as a warning.
TEST(TraineeHud, TheTraySaysWhichInstrumentIsInHand) {
  LoadResult loaded =
      load_scenario_file(std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/02_c4c5_healthy.json");
  ASSERT_TRUE(loaded.ok()) << to_string(loaded.errors);
  const ScenarioModel& scenario = *loaded.model;
  ASSERT_EQ(scenario.world.instruments.size(), 3u);
  World world(scenario.world);
  LiveView view;
  capture_world_state(world, view.state);
  view.state.frame.t_s = 10.0;
  HudModel hud = make_hud_model(scenario, world.summary(), view, HapticLoopStats{}, "mouse");
  EXPECT_EQ(hud.instrument, scenario.world.instruments[0].name);
  EXPECT_EQ(hud.tray_size, 3);
  EXPECT_TRUE(hud.alerts.empty());
  view.events.push_back(Event{9.5, EventKind::kInstrumentExchange, 2.0, "angled rongeur", -1});
  hud = make_hud_model(scenario, world.summary(), view, HapticLoopStats{}, "mouse");
  EXPECT_EQ(hud.instrument, "angled rongeur");
  ASSERT_EQ(hud.alerts.size(), 1u);
  EXPECT_EQ(hud.alerts[0].level, AlertLevel::kInfo);
  EXPECT_EQ(hud.alerts[0].text, "Took the angled rongeur from the tray");
  view.state.frame.t_s = 20.0;  // long after: still in hand, no longer announced
  hud = make_hud_model(scenario, world.summary(), view, HapticLoopStats{}, "mouse");
  EXPECT_EQ(hud.instrument, "angled rongeur");
  EXPECT_TRUE(hud.alerts.empty());
  // A scene with one instrument says nothing of a tray.
  const auto box = small_box();
  World one(box->world);
  capture_world_state(one, view.state);
  EXPECT_EQ(make_hud_model(*box, one.summary(), view, HapticLoopStats{}, "mouse").instrument, "");
}

TEST(TraineeHud, EveryHudLabelFitsAt1280x800) {
  LoadResult loaded =
      load_scenario_file(std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/02_c4c5_healthy.json");
  ASSERT_TRUE(loaded.ok()) << to_string(loaded.errors);
  World world(loaded.model->world);
  const auto& zones = world.anatomy()->zones();
  ASSERT_GE(zones.size(), 2u);
  LiveView view;
  capture_world_state(world, view.state);
  Frame& f = view.state.frame;
  f.t_s = 42.0;
  f.zones[0].inside = true;
  f.zones[1].warning = true;
  f.zones[1].distance_m = 1.2e-3f;
  f.bending_moment_Nm = 1.1 * world.summary().warning_moment_Nm;
  view.events = {Event{41.0, EventKind::kZoneEntry, 0.0, zones[0].name, 0},
                 Event{41.0, EventKind::kNeverEvent, 0.0, zones[0].name, 0},
                 Event{41.5, EventKind::kZoneForce, 1.4, zones[0].name, 0},
                 Event{41.6, EventKind::kForceClamped, 3.6, "", -1},
                 Event{41.8, EventKind::kForceClamped, 4.9, "", -1},
                 Event{41.9, EventKind::kOverloadWarning, 0.05, "", -1},
                 Event{40.5, EventKind::kInstrumentExchange, 2.0, "angled rongeur", -1}};
  HapticLoopStats loop;
  loop.rate_hz = 370;
  loop.target_rate_hz = 1000;
  loop.ticks = 20000;
  HudModel hud = make_hud_model(*loaded.model, world.summary(), view, loop, "mouse and keyboard");
  hud.mouse_mode = true;
  for (const HudAlert& a : hud.alerts) EXPECT_EQ(a.text.find('_'), std::string::npos) << a.text;

  const int w = 1280, h = 800;
  const RenderScene scene = snapshot_state(world, view.state, float(w) / h);
  std::string error;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  ASSERT_TRUE(ui) << error;
  Image im{w, h, {}};
  std::vector<std::string> overflows;
  std::vector<ImRect> windows;
  ASSERT_TRUE(ui->render(
      &scene,
      [&] {
        draw_trainee_hud(hud, ImVec2(w, h), nullptr);
        overflows = test::text_overflows(ImVec2(w, h));
        windows.clear();
        for (const char* name : {"Module", "Alerts", "Status", "Controls"})
          if (ImGuiWindow* win = ImGui::FindWindowByName(name)) windows.push_back(win->Rect());
      },
      &im.rgb, &error))
      << error;
  for (const std::string& o : overflows) ADD_FAILURE() << o;
  ASSERT_EQ(windows.size(), 4u);
  for (std::size_t a = 0; a < windows.size(); ++a)  // no HUD window covers another
    for (std::size_t b = a + 1; b < windows.size(); ++b)
      EXPECT_FALSE(windows[a].Overlaps(windows[b])) << "windows " << a << " and " << b;
  EXPECT_TRUE(write_png_rgb("trainee_hud_1280x800.png", w, h, im.rgb, &error)) << error;
}

}  // namespace
}  // namespace acdr

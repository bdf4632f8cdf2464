// The trainee view: `acdr run SCENARIO` with a display. A GLFW window on the main thread draws
// the scene at ~60 Hz from the views the haptic thread publishes (app/live_attempt.hpp), with a
// Dear ImGui overlay (ui/trainee_hud.hpp): module title and goal, time, force gauge, nucleus
// removed, zone and overload warnings, camera controls; at the end, the score screen. With no
// device the mouse and keyboard drive the instrument (ui/mouse_instrument.hpp,
// docs/trainee-view.md). The attempt session (app/attempt_session.hpp) drives it as its
// AttemptView: open, watch the live attempt, show the score.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "app/attempt_view.hpp"

namespace acdr {

struct TraineeViewOptions {
  int width = 1280;  ///< window size (screen coordinates)
  int height = 800;
  /// Write the window's picture (PNG) here, when the attempt's time first reaches
  /// `screenshot_at_s` (< 0: the last live frame, before the score screen).
  std::string screenshot;
  double screenshot_at_s = -1.0;
  /// Write the score screen's picture (PNG) here, once it is shown.
  std::string score_screenshot;
  /// Close the score screen by itself after this long (s); < 0: when the trainee closes it.
  double close_after_s = -1.0;
  bool vsync = true;
  /// Start with the bone stress view on (the scene must model the bone; key B toggles it).
  bool stress_view = false;
  std::string input_label;  ///< shown in the HUD ("udp:7000", "replay:demo.csv"); mouse: "mouse"
  /// Start with the particle materials drawn as beads (a debug view); key B toggles.
  bool beads = false;
};

class TraineeView final : public AttemptView {
 public:
  explicit TraineeView(TraineeViewOptions options);
  ~TraineeView() override;
  TraineeView(const TraineeView&) = delete;
  TraineeView& operator=(const TraineeView&) = delete;

  bool can_open() const override;
  bool open(const ScenarioModel& scenario, const World& world, InputDevice* device,
            std::string* error) override;
  InputDevice& device() override;
  void watch(LiveAttempt& live) override;
  void show_score(const AttemptRun& run, const std::string& status) override;

  /// Why a requested picture could not be written (empty: none failed).
  const std::string& picture_error() const { return picture_error_; }
  /// Frames shown so far (any thread may ask): lets a test that sends input through the X
  /// server wait until the window has read it.
  std::uint64_t frames_shown() const { return frames_shown_.load(std::memory_order_relaxed); }

 private:
  struct Window;  // GLFW, GL and ImGui: only trainee_view.cpp knows them
  TraineeViewOptions options_;
  std::unique_ptr<Window> window_;
  std::string picture_error_;
  std::atomic<std::uint64_t> frames_shown_{0};
};

}  // namespace acdr

// `acdr run`: the attempt session with the trainee view as its window, then the picture of the
// final frame and the report.
#include "cli/run_command.hpp"

#include <memory>
#include <ostream>

#include "cli/result_format.hpp"
#include "ui/offscreen_render.hpp"
#include "ui/scene_snapshot.hpp"
#include "ui/trainee_view.hpp"

namespace acdr {

int run_run(const RunOptions& options, std::ostream& out, std::ostream& err) {
  SessionOptions session = options;
  session.quiet = options.json;
  std::unique_ptr<TraineeView> view;
  if (!options.headless) {
    TraineeViewOptions window;
    window.screenshot = options.screenshot;
    window.screenshot_at_s = options.screenshot_at_s;
    window.score_screenshot = options.score_screenshot;
    window.close_after_s = options.close_after_s;
    window.stress_view = options.stress_view;
    window.input_label = options.input;
    window.beads = options.beads;
    view = std::make_unique<TraineeView>(window);
  }
  const SessionResult result = run_attempt_session(session, view.get(), err);
  if (!result.ran()) {
    if (!result.error.empty()) err << result.error << "\n";
    return result.end == SessionEnd::kLocked ? 4 : 2;
  }

  // Picture of the final frame.
  if (!options.png.empty()) {
    std::string error;
    SnapshotOptions drawing;
    drawing.drawing = options.beads ? MaterialDrawing::kBeads : MaterialDrawing::kSurfaces;
    const RenderScene scene = snapshot_world(
        *result.world,
        static_cast<float>(options.png_width) / static_cast<float>(options.png_height), {},
        drawing);
    if (!render_to_png(scene, options.png_width, options.png_height, options.png, &error)) {
      err << options.png << ": " << error << "\n";
      return 2;
    }
  }
  if (options.json)
    out << result_json(result, options.png).dump(2) << "\n";
  else
    out << result_summary(result, options.png);
  switch (result.end) {
    case SessionEnd::kRecordNotWritten:
      err << result.error << "\n";
      return 5;
    case SessionEnd::kNumericalFailure: return 1;
    case SessionEnd::kAbandoned: return 3;
    default: return 0;
  }
}

}  // namespace acdr

// `acdr render SCENARIO --png FILE [--view anterior|lateral] [--labels]`: an offscreen preview
// of a scenario's scene at t = 0 (anatomy from the surgeon's view, the front or the side); with
// a bone load (--stress-load, or a recorded attempt at a time), the stress picture of the
// loaded vertebra instead (ui/bone_stress_view.hpp).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace acdr {

struct RenderOptions {
  std::string scenario;
  std::string png;
  int width = 1280;
  int height = 800;
  /// Bone loads: each "x,y,z,fx,fy,fz" (mm, N; segment frame, force on the bone).
  std::vector<std::string> stress_loads;
  double stress_radius_mm = 1.0;  ///< patch radius of those loads
  /// Or the loads of a recorded attempt at `at_s`: a recording file (`acdr run --record`) or a
  /// stored attempt (id, database).
  std::string recording;
  std::int64_t attempt = 0;
  std::string db;
  double at_s = -1.0;  ///< < 0: the attempt's moment of peak bone load
  double stress_max_MPa = 0.0;  ///< top of the colour bar; 0: the peak, rounded up
  /// Anatomical scenes: "surgeon" (default: the disc space from the approach), "anterior" or
  /// "lateral" (the whole segment, ui/anatomy_view.hpp).
  std::string view = "surgeon";
  bool labels = false;  ///< name the parts on the picture (anterior and lateral views)
  /// Draw the particle materials as beads (a debug view of the particles) instead of surfaces.
  bool beads = false;
};

int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr

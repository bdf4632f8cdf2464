// The bone stress of an opened attempt, for the dashboard's drill-down: the disc-side bony
// endplates of C4 (its lower one, seen from below) and C5 (its upper one, seen from above),
// coloured by von Mises stress under the attempt's recorded bone loads at a chosen time, with
// the colour legend in MPa and a jump to the attempt's moment of peak bone load. The stresses
// are solved again from the recording (the scenario's bone model, meshes from the cache), one
// sample when the chosen time moves to another: nothing of it is stored with the attempt.
//
// The data side has no ImGui (testable without a screen); draw_bone_stress_pane draws it.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "app/bone_metrics_replay.hpp"
#include "assessment/attempt_recording.hpp"
#include "engine/bone/bone_segment.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

/// One vertebra's disc-side surface as drawn: triangles (corner positions in the segment
/// frame, m) and the von Mises stress of each (Pa, its tetrahedron's; in the shell the
/// shell's own).
struct EndplateSurface {
  int vertebra = 0;  ///< 0 C4 (lower endplate, seen from below), 1 C5 (upper, seen from above)
  std::vector<std::array<Vec3, 3>> triangles;  ///< far first: painter's order for the view
  std::vector<double> stress_Pa;               ///< per triangle, at the solved sample
  double endplate_peak_Pa = 0.0;  ///< the largest stress of the measured endplate elements
};

class BoneStressPane {
 public:
  /// Null (with `why` set) when the scenario does not model the bone, the recording has no bone
  /// load samples, or the bone model cannot be built.
  static std::unique_ptr<BoneStressPane> create(const ScenarioModel& scenario,
                                                const AttemptRecording& recording,
                                                std::string* why);

  /// Solves the sample at or before `t_s` (the first one before any), unless it is the one
  /// solved already.
  void show_time(double t_s);

  const EndplateSurface& surface(int vertebra) const { return surfaces_[vertebra]; }
  double sample_t_s() const { return sample_t_s_; }  ///< time of the solved sample
  double sample_load_N() const { return sample_load_N_; }
  bool sample_solved() const { return solved_any_; }  ///< some vertebra was loaded enough
  double peak_load_t_s() const { return peak_load_t_s_; }  ///< the attempt's peak bone load
  double peak_load_N() const { return peak_load_N_; }
  /// Top of the colour scale (Pa): the attempt's peak endplate stress when the record has it
  /// (set_scale_top), rounded up, so colours compare across times.
  double scale_top_Pa() const { return scale_top_Pa_; }
  void set_scale_top(double top_Pa);

 private:
  BoneStressPane() = default;
  BoneMetricsReplay replay_;
  const BoneSegment* bone_ = nullptr;
  std::vector<BoneLoadRecord> samples_;
  BoneSegmentScratch scratch_;
  std::array<EndplateSurface, 2> surfaces_;
  std::array<std::vector<std::uint32_t>, 2> face_tets_;  // per drawn triangle: its tetrahedron
  long solved_index_ = -1;
  double sample_t_s_ = 0.0, sample_load_N_ = 0.0;
  bool solved_any_ = false;
  double peak_load_t_s_ = 0.0, peak_load_N_ = 0.0;
  double scale_top_Pa_ = 1e6;
};

/// A scale top rounded up to 1, 2, 2.5 or 5 times a power of ten (Pa in, Pa out).
double nice_stress_top(double peak_Pa);

/// Draws the pane (ImGui, inside the drill-down) at `*t_s`; its "peak bone load" button sets
/// `*t_s` to that moment.
void draw_bone_stress_pane(BoneStressPane& pane, double* t_s);

}  // namespace acdr

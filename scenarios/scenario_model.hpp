// A validated, immutable scenario: the engine's WorldConfig plus what the trainee and the
// assessment need (title, goal, time limit, rubric). Built only by the loader.
#pragma once

#include <string>

#include "assessment/rubric.hpp"
#include "engine/bone/bone_segment.hpp"
#include "engine/world/world_config.hpp"

namespace acdr {

struct ScenarioModel {
  std::string path;          ///< file it was loaded from
  std::string hash;          ///< FNV-1a 64 of the file bytes, hex (stored with every attempt)
  int format_version = 1;
  std::string id;            ///< stable module id, e.g. "box-warmup"
  std::string title;
  std::string goal;          ///< learning goal in plain words
  std::string curriculum;    ///< curriculum id; empty: a stand-alone module
  int module_order = 0;      ///< position in the curriculum
  double time_limit_s = 0.0; ///< 0: none
  WorldConfig world;
  /// The bone as finite-element vertebrae (world.anatomy.bone in the file); off by default.
  BoneModelConfig bone;
  Rubric rubric;
};

}  // namespace acdr

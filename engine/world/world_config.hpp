// The engine's description of a scene: plain data, SI units, built once by the scenario loader
// (or by a test or benchmark) and never changed while a World runs. Each optional part is
// built only when present (`enabled`), so a scene pays only for what it declares. Each room's
// part is declared in that room; this gathers them.
#pragma once

#include <vector>

#include "engine/anatomy/anatomy_config.hpp"
#include "engine/core/types.hpp"
#include "engine/devices/device_config.hpp"
#include "engine/nucleus/nucleus_config.hpp"
#include "engine/rigid/instrument_config.hpp"
#include "engine/rigid/static_scene.hpp"

namespace acdr {

/// Region whose particles count as still in place; a particle that leaves it is removed.
struct RemovalRegionConfig {
  Vec3 min_m = Vec3::Zero();
  Vec3 max_m = Vec3::Zero();
};

struct WorldConfig {
  Vec3 gravity_m_s2 = Vec3(0.0, 0.0, -kStandardGravity);
  GroundConfig ground;
  OpenBoxConfig box;
  NucleusConfig nucleus;
  InstrumentConfig instrument;  ///< the instrument in hand at the start
  /// The instruments on the tray, when the scene has more than one: the first is `instrument`,
  /// and the hand exchanges them (DeviceSample::instrument) only with the instrument in hand
  /// outside the removal region. Empty: `instrument` is the only one.
  std::vector<InstrumentConfig> instruments;
  CouplingConfig coupling;
  DeviceConfig device;
  SolverConfig solver;
  RemovalRegionConfig removal;
  Pose instrument_start;  ///< grip pose at t = 0 (also the device pose until input arrives)
  AnatomyConfig anatomy;  ///< anatomy
};

}  // namespace acdr

// The small test scenes and trajectories (tests/ui/data): the test box with and without
// material, a short and a rough scoop. Shared by the tests of app/, ui/ and the command line.
#pragma once

#include <string>

namespace acdr::test {

/// The folder of the test scenes, with a trailing slash.
inline const std::string kSceneData = std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/";

}  // namespace acdr::test

// `acdr render SCENARIO --png FILE`: an offscreen preview of a scenario's scene at t = 0.
#pragma once

#include <iosfwd>
#include <string>

namespace acdr {

struct RenderOptions {
  std::string scenario;
  std::string png;
  int width = 1280;
  int height = 800;
};

int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr

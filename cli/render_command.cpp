// `acdr render`: build the scenario's world and draw it at t = 0.
#include "cli/render_command.hpp"

#include <ostream>

#include "scenarios/scenario_loader.hpp"
#include "ui/offscreen_render.hpp"
#include "ui/scene_snapshot.hpp"

namespace acdr {

int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err) {
  const LoadResult loaded = load_scenario_file(options.scenario);
  if (!loaded.ok()) {
    err << to_string(loaded.errors);
    return 2;
  }
  const World world(loaded.model->world);
  const RenderScene scene = snapshot_world(
      world, static_cast<float>(options.width) / static_cast<float>(options.height));
  std::string error;
  if (!render_to_png(scene, options.width, options.height, options.png, &error)) {
    err << options.png << ": " << error << "\n";
    return 2;
  }
  out << "wrote " << options.png << " (" << options.width << "x" << options.height << ")\n";
  return 0;
}

}  // namespace acdr

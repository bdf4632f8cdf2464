// Display detection from the environment.
#include "ui/display.hpp"

#include <cstdlib>

namespace acdr {

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wayland && *wayland);
}

}  // namespace acdr

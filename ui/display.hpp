// Whether a window can be opened at all: the commands decide between a window and a picture
// (or a headless run) before any window library is touched.
#pragma once

namespace acdr {

/// True when a window can probably be opened (DISPLAY or WAYLAND_DISPLAY set and not empty).
bool display_available();

}  // namespace acdr

// A user at the X server, for tests of live windows under Xvfb: a second X connection finds a
// window by its title and sends it pointer, wheel and key events through the XTEST extension,
// so they reach the window exactly as a person's would (through the server and GLFW). Kept
// apart from the tests so that X11's macros (None, Bool, True) do not meet GoogleTest.
#pragma once

#include <chrono>
#include <functional>

namespace acdr::test {

class XTestUser {
 public:
  XTestUser();
  ~XTestUser();
  XTestUser(const XTestUser&) = delete;
  XTestUser& operator=(const XTestUser&) = delete;

  /// Called after each group of events has reached the server, to wait until the window has
  /// read them (e.g. until it has drawn two more frames); by default a short sleep.
  void set_pace(std::function<void()> pace) { pace_ = std::move(pace); }
  /// The display opened and it has XTEST.
  bool ready() const;
  /// Waits for a mapped top-level window whose title starts with `prefix`, raises it and gives
  /// it the input focus (as a window manager would on a click); events then go to its
  /// coordinates.
  bool find_window(const char* prefix, std::chrono::milliseconds timeout);
  /// Pointer to (x, y) in the window.
  void move_to(int x, int y);
  /// Holds `button` (1 left, 2 middle, 3 right) and moves by (dx, dy) in two steps.
  void drag(unsigned button, int dx, int dy);
  /// Wheel notches: + forward (away from the user), - back.
  void wheel(int notches);
  void press_enter();

 private:
  void sync();
  std::function<void()> pace_;
  void* display_;  ///< Display*
  bool found_ = false;
  int origin_x_ = 0, origin_y_ = 0;
  int x_ = 0, y_ = 0;
};

}  // namespace acdr::test

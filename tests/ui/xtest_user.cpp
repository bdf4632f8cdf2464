// XTEST input for window tests: see xtest_user.hpp.
#include "tests/ui/xtest_user.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <thread>

#include <X11/Xlib.h>
#include <X11/extensions/XTest.h>
#include <X11/keysym.h>

namespace acdr::test {
namespace {
Display* dpy(void* d) { return static_cast<Display*>(d); }
}  // namespace

using namespace std::chrono_literals;

XTestUser::XTestUser() : display_(XOpenDisplay(nullptr)) {}
XTestUser::~XTestUser() {
  if (display_) XCloseDisplay(dpy(display_));
}

bool XTestUser::ready() const {
  int event = 0, error = 0, major = 0, minor = 0;
  return display_ && XTestQueryExtension(dpy(display_), &event, &error, &major, &minor);
}

bool XTestUser::find_window(const char* prefix, std::chrono::milliseconds timeout) {
  Display* d = dpy(display_);
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    Window root = DefaultRootWindow(d), parent = 0, *children = nullptr;
    unsigned count = 0;
    if (XQueryTree(d, root, &root, &parent, &children, &count)) {
      for (unsigned i = 0; i < count && !found_; ++i) {
        char* name = nullptr;
        if (XFetchName(d, children[i], &name) && name) {
          XWindowAttributes attributes;
          if (std::strncmp(name, prefix, std::strlen(prefix)) == 0 &&
              XGetWindowAttributes(d, children[i], &attributes) &&
              attributes.map_state == IsViewable) {
            Window child = 0;
            XTranslateCoordinates(d, children[i], root, 0, 0, &origin_x_, &origin_y_, &child);
            // What a window manager does when the user clicks the window: raise it and give
            // it the keyboard (Xvfb runs none, and GLFW reads the pointer of a focused window).
            XRaiseWindow(d, children[i]);
            XSetInputFocus(d, children[i], RevertToParent, CurrentTime);
            XSync(d, False);
            found_ = true;
          }
          XFree(name);
        }
      }
      if (children) XFree(children);
    }
    if (found_) return true;
    std::this_thread::sleep_for(50ms);
  }
  return false;
}

void XTestUser::move_to(int x, int y) {
  XTestFakeMotionEvent(dpy(display_), -1, origin_x_ + x, origin_y_ + y, CurrentTime);
  sync();
  x_ = x;
  y_ = y;
}

void XTestUser::drag(unsigned button, int dx, int dy) {
  XTestFakeButtonEvent(dpy(display_), button, True, CurrentTime);
  sync();
  const int steps = 2;
  const int x0 = x_, y0 = y_;
  for (int i = 1; i <= steps; ++i) move_to(x0 + dx * i / steps, y0 + dy * i / steps);
  sync();
  XTestFakeButtonEvent(dpy(display_), button, False, CurrentTime);
  sync();
}

void XTestUser::wheel(int notches) {
  const unsigned button = notches > 0 ? 4 : 5;
  for (int i = 0; i < std::abs(notches); ++i) {
    XTestFakeButtonEvent(dpy(display_), button, True, CurrentTime);
    XTestFakeButtonEvent(dpy(display_), button, False, CurrentTime);
  }
  sync();
}

void XTestUser::press_enter() {
  const KeyCode code = XKeysymToKeycode(dpy(display_), XK_Return);
  XTestFakeKeyEvent(dpy(display_), code, True, CurrentTime);
  sync();
  XTestFakeKeyEvent(dpy(display_), code, False, CurrentTime);
  sync();
}

void XTestUser::sync() {
  XSync(dpy(display_), False);
  if (pace_)
    pace_();
  else
    std::this_thread::sleep_for(50ms);
}

}  // namespace acdr::test

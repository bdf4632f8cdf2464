// Tests of ui/display: a display is available when DISPLAY or WAYLAND_DISPLAY names one.
#include "ui/display.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <optional>
#include <string>

namespace acdr {
namespace {

// Sets an environment variable for the test's lifetime (unset: nullopt).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      setenv(name, value->c_str(), 1);
    else
      unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      setenv(name_, old_->c_str(), 1);
    else
      unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(Display, EitherVariableNamingADisplayIsEnough) {
  {
    ScopedEnv x("DISPLAY", std::nullopt), w("WAYLAND_DISPLAY", std::nullopt);
    EXPECT_FALSE(display_available());
  }
  {
    ScopedEnv x("DISPLAY", ""), w("WAYLAND_DISPLAY", "");
    EXPECT_FALSE(display_available());  // set but empty: no display
  }
  {
    ScopedEnv x("DISPLAY", ":99"), w("WAYLAND_DISPLAY", std::nullopt);
    EXPECT_TRUE(display_available());
  }
  {
    ScopedEnv x("DISPLAY", std::nullopt), w("WAYLAND_DISPLAY", "wayland-0");
    EXPECT_TRUE(display_available());
  }
}

}  // namespace
}  // namespace acdr

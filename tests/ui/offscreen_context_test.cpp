// Tests of ui/offscreen_context: an OSMesa context renders, reads back upright, and refuses bad
// sizes with an error.
#include "ui/offscreen_context.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(OffscreenContext, GivesACoreProfileOfAtLeast33) {
  std::string error;
  auto ctx = OffscreenContext::create(64, 48, 1, &error);
  ASSERT_TRUE(ctx) << error;
  EXPECT_EQ(ctx->width(), 64);
  EXPECT_EQ(ctx->height(), 48);
  EXPECT_TRUE(ctx->core_profile()) << ctx->version();
  EXPECT_GE(std::atoi(ctx->version().c_str()), 3) << ctx->version();
  EXPECT_FALSE(ctx->renderer().empty());
  EXPECT_EQ(ctx->rgba_bottom_up().size(), 64u * 48u * 4u);
}

TEST(OffscreenContext, RefusesImpossibleSizes) {
  std::string error;
  EXPECT_FALSE(OffscreenContext::create(0, 10, 1, &error));
  EXPECT_NE(error.find("0x10"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(OffscreenContext::create(10, -3, 1, &error));
  EXPECT_FALSE(error.empty());
}

// Clears the top half red and the bottom half blue with scissor rectangles (GL's y runs up),
// then checks the image comes back with red on top: the read-back is flipped upright.
void check_upright_readback(int samples) {
  std::string error;
  auto ctx = OffscreenContext::create(40, 30, samples, &error);
  ASSERT_TRUE(ctx) << error;
  const GlFunctions& gl = ctx->gl();
  ctx->begin_frame();
  gl.Enable(GL_SCISSOR_TEST);
  gl.Scissor(0, 15, 40, 15);
  gl.ClearColor(1.0f, 0.0f, 0.0f, 0.5f);
  gl.Clear(GL_COLOR_BUFFER_BIT);
  gl.Scissor(0, 0, 40, 15);
  gl.ClearColor(0.0f, 0.0f, 1.0f, 0.5f);
  gl.Clear(GL_COLOR_BUFFER_BIT);
  gl.Disable(GL_SCISSOR_TEST);
  ASSERT_TRUE(ctx->end_frame(&error)) << error;
  const std::vector<std::uint8_t> rgb = ctx->rgb_top_down();
  ASSERT_EQ(rgb.size(), 40u * 30u * 3u);
  auto pixel = [&](int x, int y) { return &rgb[(y * 40 + x) * 3]; };
  EXPECT_EQ(pixel(5, 2)[0], 255);
  EXPECT_EQ(pixel(5, 2)[2], 0);
  EXPECT_EQ(pixel(5, 27)[0], 0);
  EXPECT_EQ(pixel(5, 27)[2], 255);
}

TEST(OffscreenContext, ReadsBackUprightWithoutMultisampling) { check_upright_readback(1); }

TEST(OffscreenContext, ReadsBackUprightThroughTheMultisampleResolve) {
  check_upright_readback(4);
}

TEST(OffscreenContext, TwoContextsKeepTheirOwnPixels) {
  std::string error;
  auto a = OffscreenContext::create(8, 8, 1, &error);
  auto b = OffscreenContext::create(8, 8, 1, &error);
  ASSERT_TRUE(a && b) << error;
  for (auto* ctx : {a.get(), b.get()}) {
    ASSERT_TRUE(ctx->make_current(&error)) << error;
    const float green = ctx == a.get() ? 1.0f : 0.0f;
    ctx->begin_frame();
    ctx->gl().ClearColor(0.0f, green, 0.0f, 1.0f);
    ctx->gl().Clear(GL_COLOR_BUFFER_BIT);
    ASSERT_TRUE(ctx->end_frame(&error)) << error;
  }
  EXPECT_EQ(a->rgb_top_down()[1], 255);
  EXPECT_EQ(b->rgb_top_down()[1], 0);
}

}  // namespace
}  // namespace acdr

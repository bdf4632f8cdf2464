// Tests of ui/png_writer: written PNGs decode (stb_image) to the same pixels, RGB only, upright.
#include "ui/png_writer.hpp"

#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>
#include <stb_image.h>

namespace acdr {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          (std::string("acdr_png_writer_test_") + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(PngWriter, WritesAnImageThatDecodesToTheSamePixels) {
  const int w = 37, h = 23;  // odd sizes catch stride mistakes
  std::vector<std::uint8_t> rgb(w * h * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &rgb[(y * w + x) * 3];
      p[0] = static_cast<std::uint8_t>(x * 7);
      p[1] = static_cast<std::uint8_t>(y * 11);
      p[2] = static_cast<std::uint8_t>((x + y) * 3);
    }
  }
  const std::string path = temp_path("gradient.png");
  std::string error;
  ASSERT_TRUE(write_png_rgb(path, w, h, rgb, &error)) << error;
  int dw = 0, dh = 0, channels = 0;
  stbi_uc* decoded = stbi_load(path.c_str(), &dw, &dh, &channels, 0);
  ASSERT_NE(decoded, nullptr) << stbi_failure_reason();
  EXPECT_EQ(dw, w);
  EXPECT_EQ(dh, h);
  EXPECT_EQ(channels, 3);  // no alpha channel in the file
  EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), decoded));
  stbi_image_free(decoded);
  std::filesystem::remove(path);
}

TEST(PngWriter, ReportsAnUnwritablePath) {
  std::string error;
  const std::string path = "/nonexistent-dir/acdr/x.png";
  EXPECT_FALSE(write_png_rgb(path, 2, 2, std::vector<std::uint8_t>(12, 0), &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
}

TEST(PngWriter, RefusesABufferOfTheWrongSize) {
  std::string error;
  EXPECT_FALSE(write_png_rgb(temp_path("bad.png"), 4, 4, std::vector<std::uint8_t>(47), &error));
  EXPECT_NE(error.find("expected 48"), std::string::npos) << error;
}

TEST(PngWriter, GlReadbackIsFlippedAndLosesItsAlpha) {
  // 1 x 2 RGBA, bottom row first: bottom pixel red with alpha 0, top pixel blue.
  const std::vector<std::uint8_t> rgba = {255, 0, 0, 0, 0, 0, 255, 128};
  const std::vector<std::uint8_t> rgb = rgba_bottom_up_to_rgb(rgba, 1, 2);
  const std::vector<std::uint8_t> expected = {0, 0, 255, 255, 0, 0};
  EXPECT_EQ(rgb, expected);
}

}  // namespace
}  // namespace acdr

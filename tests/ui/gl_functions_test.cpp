// Tests of ui/gl_functions: the table loads every entry through a loader, and names what is
// missing.
#include "ui/gl_functions.hpp"

#include <set>
#include <string>

#include <gtest/gtest.h>

#include "ui/offscreen_context.hpp"

namespace acdr {
namespace {

TEST(GlFunctions, NamesAreUniqueAndCounted) {
  const std::vector<std::string> names = GlFunctions::names();
  EXPECT_EQ(static_cast<int>(names.size()), GlFunctions::count());
  EXPECT_GT(GlFunctions::count(), 60);
  const std::set<std::string> unique(names.begin(), names.end());
  EXPECT_EQ(unique.size(), names.size());
  for (const std::string& name : names) EXPECT_EQ(name.rfind("gl", 0), 0u) << name;
}

TEST(GlFunctions, AnEmptyTableReportsEveryEntryMissing) {
  GlFunctions gl;
  EXPECT_EQ(gl.missing().size(), static_cast<std::size_t>(GlFunctions::count()));
}

TEST(GlFunctions, LoadsEveryEntryFromAnOsmesaContext) {
  std::string error;
  auto ctx = OffscreenContext::create(32, 32, 1, &error);
  ASSERT_TRUE(ctx) << error;
  const GlFunctions& gl = ctx->gl();
  EXPECT_TRUE(gl.missing().empty());
  // The pointers are live: queries through the table answer.
  const char* version = reinterpret_cast<const char*>(gl.GetString(GL_VERSION));
  ASSERT_NE(version, nullptr);
  EXPECT_GE(std::atoi(version), 3) << version;
  GLint max_texture = 0;
  gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  EXPECT_GE(max_texture, 1024);
}

TEST(GlFunctions, LoadNamesTheEntriesTheLoaderDoesNotKnow) {
  std::string error;
  auto ctx = OffscreenContext::create(16, 16, 1, &error);
  ASSERT_TRUE(ctx) << error;
  // A loader that knows everything but two names, delegating to a loaded table's source.
  const std::vector<std::string> names = GlFunctions::names();
  GlFunctions reference = ctx->gl();
  GlFunctions gl;
  const bool ok = gl.load(
      [&](const char* name) -> void* {
        const std::string n(name);
        if (n == "glBlitFramebuffer" || n == "glClear") return nullptr;
        return reinterpret_cast<void*>(reference.GetError);  // any non-null pointer
      },
      &error);
  EXPECT_FALSE(ok);
  EXPECT_NE(error.find("glBlitFramebuffer"), std::string::npos) << error;
  EXPECT_NE(error.find("glClear"), std::string::npos) << error;
  const std::vector<std::string> missing = gl.missing();
  ASSERT_EQ(missing.size(), 2u);
}

TEST(GlFunctions, ErrorStringNamesTheErrorAndTheStage) {
  std::string error;
  auto ctx = OffscreenContext::create(16, 16, 1, &error);
  ASSERT_TRUE(ctx) << error;
  const GlFunctions& gl = ctx->gl();
  EXPECT_EQ(gl_error_string(gl, "before"), "");
  gl.Enable(0xFFFF);  // not a capability
  EXPECT_EQ(gl_error_string(gl, "stage"), "stage: GL_INVALID_ENUM");
  EXPECT_EQ(gl_error_string(gl, "after"), "");  // drained
}

}  // namespace
}  // namespace acdr

// Tests of ui/dashboard_window: the dashboard's offscreen picture of a real record, and its CSV,
// written where asked, with errors that name the file. (The window loop itself is exercised by
// hand: it runs until the instructor closes it.)
#include "ui/dashboard_window.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <fstream>
#include <sstream>

#include "tests/db/db_test_support.hpp"
#include "tests/ui/test_record.hpp"

namespace acdr {
namespace {

class DashboardWindowTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    path_ = dir_->file("record.sqlite");
    test::make_test_record(path_);
  }
  static void TearDownTestSuite() { delete dir_; }
  static test::TempDir* dir_;
  static std::string path_;
};
test::TempDir* DashboardWindowTest::dir_ = nullptr;
std::string DashboardWindowTest::path_;

TEST_F(DashboardWindowTest, WritesAPictureOfTheSelectedAttempt) {
  Database db = test::open_or_fail(path_);
  auto model = load_dashboard(db);
  ASSERT_TRUE(model) << model.error().message;
  const DashboardSelection sel = default_selection(*model);
  std::string error;
  auto attempt = load_drill_down(db, sel.attempt_id, &error);
  ASSERT_TRUE(attempt) << error;
  const std::string png = dir_->file("dash.png");
  ASSERT_TRUE(write_dashboard_png(*model, sel, attempt.get(), 800, 600, png, &error)) << error;
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(png.c_str(), &w, &h, &n, 3);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 800);
  EXPECT_EQ(h, 600);
  int distinct = 0;
  for (int i = 3; i < w * h * 3; i += 3)
    distinct += data[i] != data[0] || data[i + 1] != data[1] || data[i + 2] != data[2];
  stbi_image_free(data);
  EXPECT_GT(distinct, w * h / 4);  // not blank

  EXPECT_FALSE(write_dashboard_png(*model, sel, attempt.get(), 800, 600,
                                   dir_->file("missing/dash.png"), &error));
  EXPECT_NE(error.find("missing/dash.png"), std::string::npos) << error;
}

TEST_F(DashboardWindowTest, WritesTheCsvOfTheCurrentView) {
  Database db = test::open_or_fail(path_);
  auto model = load_dashboard(db);
  ASSERT_TRUE(model);
  const DashboardSelection none;
  const std::string csv = dir_->file("progress.csv");
  std::string error;
  ASSERT_TRUE(write_dashboard_csv(*model, none, nullptr, csv, &error)) << error;
  std::ifstream in(csv);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), dashboard_csv(*model, none, nullptr));
  EXPECT_FALSE(write_dashboard_csv(*model, none, nullptr, dir_->file("missing/p.csv"), &error));
  EXPECT_EQ(error, dir_->file("missing/p.csv") + ": cannot write");
}

}  // namespace
}  // namespace acdr

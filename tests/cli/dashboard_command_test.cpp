// Tests of cli/dashboard_command.cpp: `acdr dashboard --screenshot` draws a legible,
// non-blank dashboard of a real record (text, state colours, the plots), `--export-csv`
// writes the selected view, and bad options are reported.
#include "cli/dashboard_command.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/db/db_test_support.hpp"
#include "tests/ui/image_probe.hpp"
#include "tests/ui/png_image.hpp"
#include "tests/ui/test_record.hpp"

namespace acdr {
namespace {

// Fraction of bright, near-grey pixels (ImGui text) in a rectangle.
double text_fraction(const test::Image& im, int x0, int y0, int x1, int y1) {
  int hits = 0, total = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const test::Rgb c = im.at(x, y);
      ++total;
      hits += c.r > 170 && c.g > 170 && c.b > 170;
    }
  return static_cast<double>(hits) / total;
}

class DashboardCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    db_ = dir_->file("record.sqlite");
    test::make_test_record(db_);
  }
  static void TearDownTestSuite() { delete dir_; }
  static test::TempDir* dir_;
  static std::string db_;
};
test::TempDir* DashboardCommandTest::dir_ = nullptr;
std::string DashboardCommandTest::db_;

TEST_F(DashboardCommandTest, ScreenshotShowsTheDashboardLegibly) {
  DashboardOptions o;
  o.db = db_;
  o.screenshot = dir_->file("dash.png");
  o.width = 1600;
  o.height = 1200;
  std::ostringstream out, err;
  ASSERT_EQ(run_dashboard(o, out, err), 0) << err.str();
  const test::Image im = test::load_png(o.screenshot);
  ASSERT_EQ(im.width, 1600);
  ASSERT_EQ(im.height, 1200);
  // Not blank: many distinct shades.
  int bright = 0, dark = 0;
  for (int y = 0; y < im.height; y += 4)
    for (int x = 0; x < im.width; x += 4) {
      const test::Rgb c = im.at(x, y);
      bright += c.r + c.g + c.b > 450;
      dark += c.r + c.g + c.b < 120;
    }
  EXPECT_GT(bright, 500);
  EXPECT_GT(dark, 10000);
  // Text in the trainee list (left panel) and in the metric table (lower left of the right pane).
  EXPECT_GT(text_fraction(im, 12, 40, 250, 130), 0.02);
  EXPECT_GT(text_fraction(im, 270, 420, 880, 860), 0.005);
  // State colours of the progress matrix: the mastered (dark green) cell of t-ann, and the
  // red "not passed" marker/labels.
  const double green = im.fraction([](const test::Rgb& c) {
    return c.g > 80 && c.g > c.r + 30 && c.g > c.b + 20;
  });
  const double red = im.fraction([](const test::Rgb& c) {
    return c.r > 170 && c.g < 110 && c.b < 110;
  });
  EXPECT_GT(green, 0.002);
  EXPECT_GT(red, 0.0002);
  EXPECT_NE(out.str().find("wrote"), std::string::npos);
}

TEST_F(DashboardCommandTest, ExportsTheSelectedViewAsCsv) {
  DashboardOptions o;
  o.db = db_;
  o.trainee = "t-ben";
  o.attempt = 0;  // no attempt open: the trainee's attempts
  o.export_csv = dir_->file("ben.csv");
  std::ostringstream out, err;
  ASSERT_EQ(run_dashboard(o, out, err), 0) << err.str();
  std::ifstream csv(o.export_csv);
  std::string header, row;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("attempt_id,trainee_id,module_id", 0), 0u) << header;
  int rows = 0;
  while (std::getline(csv, row)) rows += row.find("t-ben") != std::string::npos;
  EXPECT_EQ(rows, 2);
}

TEST_F(DashboardCommandTest, ReportsUnknownSelectionsAndMissingRecords) {
  std::ostringstream out, err;
  DashboardOptions o;
  o.db = db_;
  o.trainee = "t-nobody";
  o.screenshot = dir_->file("x.png");
  EXPECT_EQ(run_dashboard(o, out, err), 2);
  EXPECT_NE(err.str().find("t-nobody"), std::string::npos);
  o.trainee.clear();
  o.attempt = 424242;
  EXPECT_EQ(run_dashboard(o, out, err), 2);
  DashboardOptions missing;
  missing.db = dir_->file("typo.sqlite");
  missing.screenshot = dir_->file("y.png");
  EXPECT_EQ(run_dashboard(missing, out, err), 2);
  EXPECT_FALSE(std::filesystem::exists(missing.db));
}

}  // namespace
}  // namespace acdr

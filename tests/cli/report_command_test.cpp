// Tests of cli/report_command.cpp: exit codes, no database created by a report, and
// an attempt left running by a killed program reported as aborted.
#include "cli/report_command.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

TEST(ReportCommand, UnknownFormatIsAUsageError) {
  ReportOptions options;
  options.format = "xml";
  std::ostringstream out, err;
  EXPECT_EQ(run_report(options, out, err), 2);
  EXPECT_NE(err.str().find("xml"), std::string::npos);
  EXPECT_TRUE(out.str().empty());
}

TEST(ReportCommand, MissingDatabaseIsReportedNotCreated) {
  test::TempDir dir;
  ReportOptions options;
  options.db_path = dir.file("typo.sqlite");
  std::ostringstream out, err;
  EXPECT_EQ(run_report(options, out, err), 1);
  EXPECT_NE(err.str().find("typo.sqlite"), std::string::npos) << err.str();
  EXPECT_FALSE(std::filesystem::exists(options.db_path));
}

TEST(ReportCommand, ReportsEachFormatAndShowsInterruptedAttemptsAsAborted) {
  test::TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
    test::add_attempt(db, "t1", "m1", 80, true, test::minute(0));
    AttemptStart s;
    s.trainee_id = "t1";
    s.module_id = "m1";
    const std::int64_t id = begin_attempt(db, s).value();
    // Pretend its writer was a program on a machine/boot that is gone.
    DbResult<Statement> u = db.prepare("UPDATE attempts SET writer_host = 'gone/x' WHERE id = ?");
    ASSERT_TRUE(u->bind_all(id).ok());
    ASSERT_TRUE(u->run().ok());
  }
  ReportOptions options;
  options.db_path = path;
  options.trainee = "t1";
  for (const char* format : {"table", "csv", "json", "xapi"}) {
    options.format = format;
    std::ostringstream out, err;
    EXPECT_EQ(run_report(options, out, err), 0) << format << ": " << err.str();
    EXPECT_FALSE(out.str().empty()) << format;
    if (std::string(format) == "json") {
      const auto j = nlohmann::json::parse(out.str());
      ASSERT_EQ(j["attempts"].size(), 2u);
      EXPECT_EQ(j["attempts"][1]["status"], "aborted");
    }
    if (std::string(format) == "xapi") {
      EXPECT_EQ(nlohmann::json::parse(out.str()).size(), 2u);  // scored + passed
    }
  }
}

}  // namespace
}  // namespace acdr

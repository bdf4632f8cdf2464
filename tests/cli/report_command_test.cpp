// Tests of cli/report_command.cpp: exit codes, no database created by a report, and
// an attempt left running by a killed program reported as aborted.
#include "cli/report_command.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
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
  EXPECT_EQ(run_report(options, out, err), 2);
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

// A trainee or module the record does not hold is a mistake to report, with what it holds.
TEST(ReportCommand, UnknownTraineeOrModuleIsAClearUsageError) {
  test::TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 2);
    test::add_attempt(db, "alice", "m1", 80, true, test::minute(0));
  }
  ReportOptions options;
  options.db_path = path;
  options.trainee = "bob";
  std::ostringstream out, err;
  EXPECT_EQ(run_report(options, out, err), 2);
  EXPECT_EQ(err.str(), "acdr report: no trainee 'bob' in " + path + " (trainees: alice)\n");
  EXPECT_TRUE(out.str().empty());

  options.trainee.reset();
  options.module = "m9";
  std::ostringstream out2, err2;
  EXPECT_EQ(run_report(options, out2, err2), 2);
  EXPECT_EQ(err2.str(), "acdr report: no module 'm9' in " + path + " (modules: m1, m2)\n");
}

// CSV values are rounded to nine significant digits: a duration summed over 1 ms steps reads
// 9.8, not 9.800000000000008.
TEST(ReportCommand, CsvValuesAreRounded) {
  test::TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
    AttemptStart start;
    start.trainee_id = "alice";
    start.module_id = "m1";
    const std::int64_t id = begin_attempt(db, start).value();
    AttemptOutcome outcome = test::make_outcome(61.20000000000001, true);
    double t = 0.0;
    for (int i = 0; i < 9800; ++i) t += 1e-3;  // 9.8 with the round-off of many steps
    ASSERT_NE(t, 9.8);
    outcome.duration_s = t;
    outcome.metrics.set("time_over_warning_s", t);
    outcome.metrics.set("peak_bending_moment_Nm", 0.012345678901);
    ASSERT_TRUE(finish_attempt(db, id, outcome).ok());
  }
  ReportOptions options;
  options.db_path = path;
  options.format = "csv";
  std::ostringstream out, err;
  ASSERT_EQ(run_report(options, out, err), 0) << err.str();
  const std::string csv = out.str();
  EXPECT_EQ(csv.find("00000000"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("99999999"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",9.8,0.85,61.2,"), std::string::npos) << csv;  // duration, real time, score
  EXPECT_NE(csv.find(",0.0123456789"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",9.8"), csv.rfind(",9.8")) << "the metric is rounded too:\n" << csv;
}

}  // namespace
TEST(ReportCommand, XapiTakesTheActivityIriBaseFromTheLrsConfiguration) {
  test::TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
    test::add_attempt(db, "t1", "m1", 80, true, test::minute(0));
  }
  unsetenv("ACDR_XAPI_IRI_BASE");
  unsetenv("ACDR_LRS_CONFIG");
  const std::string config = dir.file("lrs.json");
  std::ofstream(config) << R"({"activity_iri_base": "https://training.example.org/acdr/"})";
  ReportOptions options;
  options.db_path = path;
  options.format = "xapi";
  options.lrs_config = config;
  std::ostringstream out, err;
  ASSERT_EQ(run_report(options, out, err), 0) << err.str();
  for (const auto& st : nlohmann::json::parse(out.str())) {
    EXPECT_EQ(st["object"]["id"], "https://training.example.org/acdr/modules/m1");
  }
  // The environment wins over the file.
  setenv("ACDR_XAPI_IRI_BASE", "https://other.example.org/", 1);
  std::ostringstream out2, err2;
  ASSERT_EQ(run_report(options, out2, err2), 0) << err2.str();
  unsetenv("ACDR_XAPI_IRI_BASE");
  EXPECT_EQ(nlohmann::json::parse(out2.str())[0]["object"]["id"],
            "https://other.example.org/modules/m1");
  // A bad base is refused with the file named.
  std::ofstream(config) << R"({"activity_iri_base": "acdr"})";
  std::ostringstream out3, err3;
  EXPECT_EQ(run_report(options, out3, err3), 2);
  EXPECT_NE(err3.str().find(config), std::string::npos) << err3.str();
}

}  // namespace acdr

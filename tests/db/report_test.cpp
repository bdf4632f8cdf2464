// Tests of db/report.cpp: CSV (RFC 4180) and JSON parse back to the stored values, the table
// shows what an instructor needs, filters apply.
#include "db/report.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using test::add_attempt;
using test::minute;

// A strict RFC 4180 reader: CRLF records, quoted fields with doubled quotes.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      EXPECT_TRUE(field.empty()) << "quote inside an unquoted field";
      quoted = true;
    } else if (c == ',') {
      row.push_back(field);
      field.clear();
    } else if (c == '\r') {
      EXPECT_TRUE(i + 1 < text.size() && text[i + 1] == '\n') << "CR without LF";
      row.push_back(field);
      field.clear();
      rows.push_back(row);
      row.clear();
      ++i;
    } else {
      EXPECT_NE(c, '\n') << "bare LF outside quotes";
      field += c;
    }
  }
  EXPECT_FALSE(quoted);
  EXPECT_TRUE(field.empty() && row.empty()) << "last record must end with CRLF";
  return rows;
}

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_ = test::open_or_fail(dir_.file("record.sqlite"));
    test::register_curriculum(db_, 2);
    expert_ = add_attempt(db_, "t1", "m1", 82.5, true, minute(0));
    novice_ = add_attempt(db_, "t1", "m1", 31.0, false, minute(1));
    other_ = add_attempt(db_, tricky_, "m2", 55.0, true, minute(2));
    practice_ = add_attempt(db_, std::nullopt, "m1", 60.0, true, minute(3));
    AttemptStart s;
    s.trainee_id = "t1";
    s.module_id = "m1";
    s.started_utc = minute(4);
    aborted_ = begin_attempt(db_, s).value();
    EXPECT_TRUE(abort_attempt(db_, aborted_, "killed").ok());
  }
  std::string report(ReportFormat format, std::optional<std::string> trainee = std::nullopt,
                     std::optional<std::string> module = std::nullopt) {
    ReportRequest r;
    r.format = format;
    r.trainee_id = std::move(trainee);
    r.module_id = std::move(module);
    std::ostringstream out;
    DbStatus s = write_report(db_, r, out);
    EXPECT_TRUE(s.ok()) << s.error().message;
    return out.str();
  }

  test::TempDir dir_;
  Database db_;
  const std::string tricky_ = "=\"Smith, J\"; DROP\nTABLE";
  std::int64_t expert_ = 0, novice_ = 0, other_ = 0, practice_ = 0, aborted_ = 0;
};

TEST_F(ReportTest, CsvHasAHeaderAndOneQuotedRowPerAttempt) {
  const std::string csv = report(ReportFormat::kCsv);
  const auto rows = parse_csv(csv);
  ASSERT_EQ(rows.size(), 6u);  // header + 5 attempts
  const auto& header = rows[0];
  auto col = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  for (const auto& row : rows) EXPECT_EQ(row.size(), header.size());
  EXPECT_EQ(rows[1][col("attempt_id")], std::to_string(expert_));
  EXPECT_EQ(rows[1][col("trainee")], "t1");
  EXPECT_EQ(rows[1][col("score")], "82.5");
  EXPECT_EQ(rows[1][col("passed")], "true");
  EXPECT_EQ(rows[1][col("nucleus_removed_fraction")], "0.825");
  EXPECT_EQ(rows[2][col("passed")], "false");
  // Commas, quotes and newlines survive; a formula-looking cell is defused with a quote.
  EXPECT_EQ(rows[3][col("trainee")], "'" + tricky_);
  EXPECT_EQ(rows[4][col("trainee")], "");
  EXPECT_EQ(rows[5][col("status")], "aborted");
  EXPECT_EQ(rows[5][col("abort_reason")], "killed");
  EXPECT_EQ(rows[5][col("score")], "");
  EXPECT_EQ(rows[1][col("realtime_factor")], "0.85");  // as the attempt ran
  EXPECT_EQ(rows[5][col("realtime_factor")], "");      // an aborted attempt does not know it
}

TEST_F(ReportTest, JsonParsesBackWithAttemptsEventsAndProgress) {
  const nlohmann::json j = nlohmann::json::parse(report(ReportFormat::kJson, "t1"));
  EXPECT_EQ(j["format"], "acdr-report");
  EXPECT_EQ(j["filter"]["trainee"], "t1");
  ASSERT_EQ(j["attempts"].size(), 3u);
  const auto& expert = j["attempts"][0];
  EXPECT_EQ(expert["id"], expert_);
  EXPECT_EQ(expert["score"], 82.5);
  EXPECT_EQ(expert["passed"], true);
  EXPECT_EQ(expert["metrics"]["peak_instrument_force_N"], 3.5);
  ASSERT_EQ(expert["events"].size(), 1u);
  EXPECT_EQ(expert["events"][0]["kind"], "zone_warning");
  EXPECT_EQ(expert["events"][0]["zone"], "foramen_left");
  EXPECT_EQ(j["attempts"][1]["reasons"][0], "score below the pass line");
  EXPECT_EQ(j["attempts"][2]["status"], "aborted");
  EXPECT_TRUE(j["attempts"][2]["score"].is_null());
  EXPECT_EQ(expert["realtime_factor"], 0.85);
  EXPECT_TRUE(j["attempts"][2]["realtime_factor"].is_null());

  ASSERT_EQ(j["progress"].size(), 1u);
  EXPECT_EQ(j["progress"][0]["trainee"], "t1");
  const auto& m1 = j["progress"][0]["modules"][0];
  EXPECT_EQ(m1["module"], "m1");
  EXPECT_EQ(m1["attempts"], 3);
  EXPECT_EQ(m1["passes"], 1);
  EXPECT_EQ(m1["mastered"], false);
  EXPECT_EQ(j["progress"][0]["modules"][1]["unlocked"], false);
}

TEST_F(ReportTest, FiltersApplyToEveryFormat) {
  const nlohmann::json by_module = nlohmann::json::parse(report(ReportFormat::kJson,
                                                                std::nullopt, "m2"));
  ASSERT_EQ(by_module["attempts"].size(), 1u);
  EXPECT_EQ(by_module["attempts"][0]["trainee"], tricky_);
  ASSERT_EQ(by_module["progress"].size(), 1u);
  EXPECT_EQ(by_module["progress"][0]["modules"].size(), 1u);
  EXPECT_EQ(parse_csv(report(ReportFormat::kCsv, "t1", "m1")).size(), 4u);
  EXPECT_EQ(parse_csv(report(ReportFormat::kCsv, "nobody")).size(), 1u);
}

TEST_F(ReportTest, TableShowsAttemptsAndProgress) {
  const std::string table = report(ReportFormat::kTable, "t1");
  EXPECT_NE(table.find("Attempts (3)"), std::string::npos) << table;
  EXPECT_NE(table.find("82.5"), std::string::npos);
  EXPECT_NE(table.find("FAIL"), std::string::npos);
  EXPECT_NE(table.find("aborted"), std::string::npos);
  EXPECT_NE(table.find("Progress of trainee t1"), std::string::npos);
  EXPECT_NE(table.find("locked"), std::string::npos);
  EXPECT_NE(table.find("real time"), std::string::npos) << table;
  EXPECT_NE(table.find("0.85x"), std::string::npos) << table;  // the attempts' real-time factor
  // Aligned: every line of the attempts block has its "score" column at the same offset.
  std::istringstream lines(table);
  std::string line, header;
  std::getline(lines, line);
  std::getline(lines, header);
  const std::size_t status_col = header.find("status");
  ASSERT_NE(status_col, std::string::npos);
  std::getline(lines, line);  // rule
  for (int i = 0; i < 3 && std::getline(lines, line); ++i) {
    const std::string cell = line.substr(status_col, 9);
    EXPECT_TRUE(cell.rfind("completed", 0) == 0 || cell.rfind("aborted", 0) == 0) << line;
  }
}

TEST(ReportFormat, ParsesTheFourNames) {
  EXPECT_EQ(parse_report_format("table"), std::optional<ReportFormat>(ReportFormat::kTable));
  EXPECT_EQ(parse_report_format("csv"), std::optional<ReportFormat>(ReportFormat::kCsv));
  EXPECT_EQ(parse_report_format("json"), std::optional<ReportFormat>(ReportFormat::kJson));
  EXPECT_EQ(parse_report_format("xapi"), std::optional<ReportFormat>(ReportFormat::kXapi));
  EXPECT_FALSE(parse_report_format("XML").has_value());
}

}  // namespace
}  // namespace acdr

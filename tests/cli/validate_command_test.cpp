// `acdr validate`: OK lines for good files, every error for bad ones, and the exit status.
#include "cli/validate_command.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace acdr {
namespace {

std::string module_path() { return std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/01_box_warmup.json"; }

std::string write_temp(const std::string& name, const std::string& text) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

TEST(ValidateCommand, GoodFilePrintsOkAndReturnsZero) {
  std::ostringstream out;
  EXPECT_EQ(run_validate({module_path()}, out), 0);
  // The verdict and what the scenario will cost to run.
  EXPECT_EQ(out.str().rfind("OK " + module_path() + " (about ", 0), 0u) << out.str();
  EXPECT_NE(out.str().find(" particles, "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find(" frames, "), std::string::npos) << out.str();
}

TEST(ValidateCommand, BadFilePrintsEveryErrorAndReturnsNonZero) {
  const std::string bad = write_temp("acdr_validate_bad.json",
                                     "{\n  \"format_version\": 1,\n  \"idd\": \"x\"\n}\n");
  std::ostringstream out;
  EXPECT_EQ(run_validate({module_path(), bad}, out), 1);
  const std::string text = out.str();
  EXPECT_NE(text.find("OK " + module_path()), std::string::npos);
  EXPECT_NE(text.find(bad + ":3: /idd: unknown key (did you mean \"id\"?)"), std::string::npos) << text;
  EXPECT_NE(text.find(bad + ":1: /title: missing required key"), std::string::npos) << text;
  EXPECT_NE(text.find("1 of 2 files valid"), std::string::npos) << text;
  std::remove(bad.c_str());
}

TEST(ValidateCommand, TruncatedAndMissingFilesFail) {
  const std::string cut = write_temp("acdr_validate_cut.json", "{\n  \"format_version\": 1,\n  \"id\": ");
  std::ostringstream out;
  EXPECT_EQ(run_validate({cut, "/nonexistent/x.json"}, out), 1);
  EXPECT_NE(out.str().find(cut + ":3: the file ends before the JSON is complete"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("/nonexistent/x.json:0: cannot open"), std::string::npos) << out.str();
  std::remove(cut.c_str());
}

TEST(ValidateCommand, NoFilesIsAUsageError) {
  std::ostringstream out;
  EXPECT_EQ(run_validate({}, out), 2);
  EXPECT_FALSE(out.str().empty());
}

}  // namespace
}  // namespace acdr

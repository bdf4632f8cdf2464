// `acdr verify` and `acdr stress` bodies: exit codes and output formats.
#include "cli/verify_command.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace acdr {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(VerifyCommand, CaseFileRunsAndPrintsTheIssueJson) {
  VerifyOptions o;
  o.json = true;
  o.fast = true;
  o.case_files = {write_temp("cases.json", R"({"cases": [{"case": "oscillator"},
      {"case": "couette_shear", "parameters": {"viscosity_Pa_s": 40}}]})")};
  std::ostringstream out, err;
  EXPECT_EQ(run_verify(o, out, err), 0) << out.str() << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  ASSERT_EQ(doc["cases"].size(), 2u);
  for (const char* key : {"name", "quantity", "simulated", "analytic", "rel_error", "tolerance", "passed"})
    EXPECT_TRUE(doc["cases"][0].contains(key)) << key;
  EXPECT_TRUE(doc["passed"].get<bool>());
}

TEST(VerifyCommand, AFailingCaseExitsNonZero) {
  VerifyOptions o;
  o.fast = true;
  o.case_files = {write_temp("coarse.json",
                             R"({"case": "oscillator", "parameters": {"dt_s": 0.001}})")};
  std::ostringstream out, err;
  EXPECT_EQ(run_verify(o, out, err), 1);
  EXPECT_NE(out.str().find("FAILED"), std::string::npos);
}

TEST(VerifyCommand, ABadCaseFileExitsTwoWithItsErrors) {
  VerifyOptions o;
  o.case_files = {write_temp("bad.json", R"({"case": "nope"})")};
  std::ostringstream out, err;
  EXPECT_EQ(run_verify(o, out, err), 2);
  EXPECT_NE(err.str().find("bad.json:1"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace acdr

// Verification case files: good files give specs with the author's parameters; bad ones give
// located errors naming the path, the value and what was expected.
#include "scenarios/verification_case_file.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(VerificationCaseFile, ReadsCasesWithTheirParameters) {
  const auto f = parse_verification_case_file(R"({
  "cases": [
    {"case": "couette_shear", "name": "stiff gel", "parameters": {"viscosity_Pa_s": 1000, "gap_m": 0.005}},
    {"case": "oscillator"}
  ]
})",
                                              "mine.json");
  ASSERT_TRUE(f.ok()) << to_string(f.errors);
  ASSERT_EQ(f.cases.size(), 2u);
  EXPECT_EQ(f.cases[0].name, "stiff gel");
  EXPECT_EQ(f.cases[0].kind, "couette_shear");
  EXPECT_DOUBLE_EQ(f.cases[0].get("viscosity_Pa_s"), 1000.0);
  EXPECT_DOUBLE_EQ(f.cases[0].get("gap_m"), 0.005);
  EXPECT_EQ(f.cases[1].name, "oscillator");
}

TEST(VerificationCaseFile, AcceptsASingleCaseObject) {
  const auto f = parse_verification_case_file(R"({"case": "bond_break"})", "one.json");
  ASSERT_TRUE(f.ok());
  ASSERT_EQ(f.cases.size(), 1u);
}

TEST(VerificationCaseFile, UnknownCaseAndParameterAreLocatedErrors) {
  const auto f = parse_verification_case_file(R"({
  "cases": [
    {"case": "couete_shear"},
    {"case": "buoyancy", "parameters": {"viscosty_Pa_s": 10, "dt_s": -1}}
  ]
})",
                                              "bad.json");
  ASSERT_EQ(f.errors.size(), 3u) << to_string(f.errors);
  EXPECT_TRUE(f.cases.empty());
  EXPECT_EQ(f.errors[0].file, "bad.json");
  EXPECT_EQ(f.errors[0].line, 3);
  EXPECT_EQ(f.errors[0].json_path, "/cases/0/case");
  EXPECT_NE(f.errors[0].message.find("couette_shear"), std::string::npos);  // suggestion
  const std::string all = to_string(f.errors);
  EXPECT_NE(all.find("/cases/1/parameters/viscosty_Pa_s"), std::string::npos);
  EXPECT_NE(all.find("viscosity_Pa_s"), std::string::npos);
  EXPECT_NE(all.find("/cases/1/parameters/dt_s"), std::string::npos);
  EXPECT_NE(all.find("> 0"), std::string::npos);
}

TEST(VerificationCaseFile, MalformedJsonNamesTheLine) {
  const auto f = parse_verification_case_file("{\n  \"cases\": [\n  {\"case\": }\n]}", "broken.json");
  ASSERT_EQ(f.errors.size(), 1u);
  EXPECT_EQ(f.errors[0].line, 3);
}

TEST(VerificationCaseFile, MissingFileIsAnError) {
  const auto f = load_verification_case_file("/nonexistent/cases.json");
  ASSERT_EQ(f.errors.size(), 1u);
  EXPECT_EQ(f.errors[0].file, "/nonexistent/cases.json");
}

}  // namespace
}  // namespace acdr

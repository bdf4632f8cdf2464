// A rubric written back into a scenario file: the file still loads, gives the same rubric (to
// the four digits benchmarks are written with), and keeps the rest of its text.
#include "scenarios/rubric_fragment.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "scenarios/scenario_loader.hpp"
#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

TEST(RubricFragment, ReplacingAModulesRubricKeepsTheRestOfTheFile) {
  const std::string path = test::source_path("scenarios/modules/04_full_discectomy.json");
  const std::string original = test::read_text(path);
  const LoadResult before = load_scenario_text(original, path);
  ASSERT_TRUE(before.ok()) << to_string(before.errors);
  Rubric changed = before.model->rubric;
  changed.terms[0].expert_mean = 0.5432109;  // written as 0.5432
  changed.terms[1].expert_sd = 2.5;
  changed.task->min = 0.1358;
  changed.pass_score = 40;
  std::string text = original;
  std::string error;
  ASSERT_TRUE(replace_rubric(text, changed, &error)) << error;
  const LoadResult after = load_scenario_text(text, path);
  ASSERT_TRUE(after.ok()) << to_string(after.errors);
  const Rubric& r = after.model->rubric;
  ASSERT_EQ(r.terms.size(), changed.terms.size());
  for (std::size_t i = 0; i < r.terms.size(); ++i) {
    EXPECT_EQ(r.terms[i].metric, changed.terms[i].metric);
    EXPECT_NEAR(r.terms[i].expert_mean, changed.terms[i].expert_mean, 1e-4 * std::abs(changed.terms[i].expert_mean) + 1e-12);
    EXPECT_DOUBLE_EQ(r.terms[i].expert_sd, changed.terms[i].expert_sd);
    EXPECT_EQ(r.terms[i].higher_is_better, changed.terms[i].higher_is_better);
    EXPECT_EQ(r.terms[i].weight, changed.terms[i].weight);
    EXPECT_EQ(r.terms[i].safety, changed.terms[i].safety);
    EXPECT_EQ(r.terms[i].sd_floor, changed.terms[i].sd_floor);
  }
  EXPECT_DOUBLE_EQ(r.terms[0].expert_mean, 0.5432);
  ASSERT_EQ(r.gates.size(), changed.gates.size());
  for (std::size_t i = 0; i < r.gates.size(); ++i) {
    EXPECT_EQ(r.gates[i].metric, changed.gates[i].metric);
    EXPECT_EQ(r.gates[i].max, changed.gates[i].max);
  }
  EXPECT_DOUBLE_EQ(r.task->min, 0.1358);
  EXPECT_DOUBLE_EQ(r.pass_score, 40);
  EXPECT_EQ(r.consecutive_passes_to_master, changed.consecutive_passes_to_master);
  // Everything before the rubric is byte for byte the same.
  const std::size_t at = original.find("\"rubric\"");
  EXPECT_EQ(text.substr(0, at), original.substr(0, at));
  // Writing the loaded rubric back gives the file it came from, once written in this layout.
  std::string again = text;
  ASSERT_TRUE(replace_rubric(again, r, &error));
  EXPECT_EQ(again, text);
}

TEST(RubricFragment, AFileWithoutARubricIsRefused) {
  std::string text = "{\n  \"id\": \"x\",\n  \"world\": { \"rubric\": {} }\n}\n";
  std::string error;
  EXPECT_FALSE(replace_rubric(text, Rubric{}, &error));
  EXPECT_NE(error.find("no top-level \"rubric\" object"), std::string::npos) << error;
}

}  // namespace
}  // namespace acdr

// The modules of a curriculum from a folder of scenario files: the bundled set, and a folder
// with files that are not scenarios or repeat a module id.
#include "scenarios/curriculum_set.hpp"

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <gtest/gtest.h>

#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

TEST(CurriculumSet, TheBundledModulesInTheirOrder) {
  const CurriculumSet set = load_curriculum_set(test::source_path("scenarios/modules"), "acdr-scooping");
  EXPECT_TRUE(set.skipped.empty());
  ASSERT_EQ(set.modules.size(), 4u);
  EXPECT_EQ(set.modules[0]->id, "box-warmup");
  EXPECT_EQ(set.modules[1]->id, "c4c5-healthy");
  for (std::size_t i = 1; i < set.modules.size(); ++i)
    EXPECT_LT(set.modules[i - 1]->module_order, set.modules[i]->module_order);
  EXPECT_TRUE(load_curriculum_set(test::source_path("scenarios/modules"), "other").modules.empty());
}

TEST(CurriculumSet, OtherFilesAreSkippedWithTheirName) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("acdr_curriculum_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string box = test::box_module_text();
  std::ofstream(dir / "a.json") << box;
  std::ofstream(dir / "b.json") << box;                 // the same module id again
  std::ofstream(dir / "broken.json") << "{ \"id\": ";   // not a scenario
  std::ofstream(dir / "notes.txt") << "not json";       // not looked at
  const CurriculumSet set = load_curriculum_set(dir.string(), "acdr-scooping");
  ASSERT_EQ(set.modules.size(), 1u);
  EXPECT_EQ(set.modules[0]->path, (dir / "a.json").string());
  ASSERT_EQ(set.skipped.size(), 2u);
  EXPECT_NE(set.skipped[0].find("b.json: module id 'box-warmup' is already taken"), std::string::npos)
      << set.skipped[0];
  EXPECT_NE(set.skipped[1].find("broken.json: not a valid scenario"), std::string::npos) << set.skipped[1];
  const CurriculumSet missing = load_curriculum_set((dir / "nowhere").string(), "acdr-scooping");
  EXPECT_TRUE(missing.modules.empty());
  ASSERT_EQ(missing.skipped.size(), 1u);
  EXPECT_NE(missing.skipped[0].find("cannot list the folder"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace acdr

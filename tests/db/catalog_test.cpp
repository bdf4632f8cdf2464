// Tests of db/catalog.cpp: registering trainees, curricula and modules; module versions;
// implicit prerequisites from curriculum order.
#include "db/catalog.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using test::TempDir;

TEST(Catalog, TraineeUpsertKeepsCreationTimeAndName) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"t1", "First", "2024-01-01T00:00:00.000Z"}).ok());
  ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"t1", "", "2025-01-01T00:00:00.000Z"}).ok());
  TraineeRecord t = *find_trainee(db, "t1").value();
  EXPECT_EQ(t.display_name, "First");
  EXPECT_EQ(t.created_utc, "2024-01-01T00:00:00.000Z");
  ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"t1", "Renamed", ""}).ok());
  EXPECT_EQ(find_trainee(db, "t1").value()->display_name, "Renamed");
  EXPECT_FALSE(find_trainee(db, "t2").value().has_value());
  EXPECT_FALSE(upsert_trainee(db, TraineeRecord{"", "x", ""}).ok());
  EXPECT_EQ(list_trainees(db).value().size(), 1u);
}

TEST(Catalog, ModuleVersionFollowsTheScenarioHash) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  ModuleRecord m;
  m.id = "box";
  m.scenario_hash = "aaaa";
  EXPECT_EQ(upsert_module(db, m).value().version, 1);
  EXPECT_EQ(upsert_module(db, m).value().version, 1);
  m.scenario_hash = "bbbb";
  m.title = "Box";
  const ModuleRecord stored = upsert_module(db, m).value();
  EXPECT_EQ(stored.version, 2);
  EXPECT_EQ(stored.title, "Box");
  EXPECT_FALSE(stored.prerequisites.has_value());
}

TEST(Catalog, ModuleInputIsValidated) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  ModuleRecord m;
  m.id = "box";
  m.consecutive_passes_required = 0;
  DbResult<ModuleRecord> r = upsert_module(db, m);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("consecutive_passes_required is 0"), std::string::npos);
  m.consecutive_passes_required = 2;
  m.pass_score = std::nan("");
  EXPECT_FALSE(upsert_module(db, m).ok());
  m.pass_score = 50;
  m.curriculum_id = "missing";
  r = upsert_module(db, m);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("'missing'"), std::string::npos);
  m.curriculum_id.reset();
  m.prerequisites = std::vector<std::string>{"box"};
  EXPECT_FALSE(upsert_module(db, m).ok());
  EXPECT_TRUE(list_modules(db).value().empty());
}

TEST(Catalog, ImplicitPrerequisitesAreTheModulesJustBefore) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 3);
  ModuleRecord parallel;  // same position as m2: both unlock m3
  parallel.id = "m2b";
  parallel.curriculum_id = "acdr";
  parallel.position = 2;
  ASSERT_TRUE(upsert_module(db, parallel).ok());

  auto prereqs = [&](const std::string& id) {
    return effective_prerequisites(db, *find_module(db, id).value()).value();
  };
  EXPECT_TRUE(prereqs("m1").empty());
  EXPECT_EQ(prereqs("m2"), std::vector<std::string>{"m1"});
  EXPECT_EQ(prereqs("m3"), (std::vector<std::string>{"m2", "m2b"}));

  const auto modules = list_modules(db, std::string("acdr")).value();
  ASSERT_EQ(modules.size(), 4u);
  EXPECT_EQ(modules[0].id, "m1");
  EXPECT_EQ(modules[3].id, "m3");
  EXPECT_EQ(list_curricula(db).value().size(), 1u);
}

}  // namespace
}  // namespace acdr

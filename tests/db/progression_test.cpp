// Tests of db/progression.cpp: the N-in-a-row mastery rule, unlocking by prerequisites, and
// which attempts count.
#include "db/progression.hpp"

#include <gtest/gtest.h>

#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using test::add_attempt;
using test::minute;
using test::TempDir;
constexpr auto P = CountedOutcome::kPassed;
constexpr auto F = CountedOutcome::kFailed;
constexpr auto A = CountedOutcome::kAborted;

RunSummary run(std::initializer_list<CountedOutcome> outcomes, int required = 2,
               bool aborted_breaks = true) {
  const std::vector<CountedOutcome> v(outcomes);
  return summarize_run(v, required, ProgressionOptions{aborted_breaks});
}

TEST(SummarizeRun, TwoPassesInARowMaster) {
  EXPECT_FALSE(run({}).mastered);
  EXPECT_FALSE(run({P}).mastered);
  EXPECT_TRUE(run({P, P}).mastered);
  EXPECT_FALSE(run({P, F, P}).mastered);
  EXPECT_EQ(run({P, F, P}).consecutive_at_end, 1);
  EXPECT_EQ(run({P, F, P}).passes, 2);

  const RunSummary late = run({F, P, F, P, P});
  EXPECT_TRUE(late.mastered);
  EXPECT_EQ(late.mastered_at, 5);
  EXPECT_EQ(late.attempts, 5);
  EXPECT_EQ(late.longest_run, 2);
}

TEST(SummarizeRun, MasteryIsKeptAfterALaterFail) {
  const RunSummary r = run({P, P, F});
  EXPECT_TRUE(r.mastered);
  EXPECT_EQ(r.mastered_at, 2);
  EXPECT_EQ(r.consecutive_at_end, 0);
}

TEST(SummarizeRun, RequiredCountComesFromTheModule) {
  EXPECT_FALSE(run({P, P}, 3).mastered);
  EXPECT_TRUE(run({P, P, P}, 3).mastered);
  EXPECT_TRUE(run({P}, 1).mastered);
}

TEST(SummarizeRun, AbortedAttemptsBreakTheRunUnlessToldOtherwise) {
  EXPECT_FALSE(run({P, A, P}).mastered);
  EXPECT_EQ(run({P, A, P}).attempts, 3);
  EXPECT_TRUE(run({P, A, P}, 2, false).mastered);
  EXPECT_EQ(run({P, A, P}, 2, false).attempts, 2);
}

class ProgressionDb : public ::testing::Test {
 protected:
  void SetUp() override {
    db_ = test::open_or_fail(dir_.file("record.sqlite"));
    test::register_curriculum(db_, 3);
  }
  bool unlocked(const std::string& trainee, const std::string& module) {
    DbResult<UnlockDecision> d = check_unlocked(db_, trainee, module);
    EXPECT_TRUE(d.ok()) << d.error().message;
    return d.ok() && d->unlocked;
  }
  TempDir dir_;
  Database db_;
};

TEST_F(ProgressionDb, FirstModuleIsOpenAndTheNextOpensAfterTwoPassesInARow) {
  EXPECT_TRUE(unlocked("t1", "m1"));
  EXPECT_FALSE(unlocked("t1", "m2"));

  add_attempt(db_, "t1", "m1", 70, true, minute(0));
  EXPECT_FALSE(unlocked("t1", "m2")) << "one pass must not unlock";
  ModuleProgress p = module_progress(db_, "t1", "m1").value();
  EXPECT_TRUE(p.passed);
  EXPECT_FALSE(p.mastered);
  EXPECT_EQ(p.run.consecutive_at_end, 1);

  add_attempt(db_, "t1", "m1", 72, true, minute(1));
  EXPECT_TRUE(unlocked("t1", "m2")) << "two consecutive passes unlock";
  EXPECT_FALSE(unlocked("t1", "m3"));
  p = module_progress(db_, "t1", "m1").value();
  EXPECT_TRUE(p.mastered);
  EXPECT_EQ(p.best_score, std::optional<double>(72));
  EXPECT_STREQ(p.state_name(), "mastered");
}

TEST_F(ProgressionDb, PassFailPassDoesNotUnlock) {
  add_attempt(db_, "t1", "m1", 70, true, minute(0));
  add_attempt(db_, "t1", "m1", 30, false, minute(1));
  add_attempt(db_, "t1", "m1", 70, true, minute(2));
  EXPECT_FALSE(unlocked("t1", "m2"));
  DbResult<UnlockDecision> d = check_unlocked(db_, "t1", "m2");
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->missing_prerequisites, std::vector<std::string>{"m1"});
  EXPECT_NE(d->reason.find("'m1'"), std::string::npos) << d->reason;
  EXPECT_NE(d->reason.find("2 attempts in a row"), std::string::npos) << d->reason;
  // Order is by start time, not by insertion: a pass started later completes the run.
  add_attempt(db_, "t1", "m1", 70, true, minute(3));
  EXPECT_TRUE(unlocked("t1", "m2"));
}

TEST_F(ProgressionDb, PracticeAndOtherTraineesAttemptsNeverCount) {
  add_attempt(db_, std::nullopt, "m1", 90, true, minute(0));
  add_attempt(db_, std::nullopt, "m1", 90, true, minute(1));
  add_attempt(db_, "t2", "m1", 90, true, minute(2));
  add_attempt(db_, "t2", "m1", 90, true, minute(3));
  EXPECT_FALSE(unlocked("t1", "m2"));
  EXPECT_EQ(module_progress(db_, "t1", "m1").value().run.attempts, 0);
  EXPECT_TRUE(unlocked("t2", "m2"));
}

TEST_F(ProgressionDb, RunningAttemptsAreNotYetAnOutcomeButAbortedOnesBreakTheRun) {
  add_attempt(db_, "t1", "m1", 70, true, minute(0));
  AttemptStart s;
  s.trainee_id = "t1";
  s.module_id = "m1";
  s.started_utc = minute(1);
  const std::int64_t running = begin_attempt(db_, s).value();
  add_attempt(db_, "t1", "m1", 70, true, minute(2));
  EXPECT_TRUE(unlocked("t1", "m2")) << "a running attempt is not counted";

  ASSERT_TRUE(abort_attempt(db_, running, "quit").ok());
  EXPECT_FALSE(unlocked("t1", "m2")) << "an aborted attempt between the passes breaks the run";
  EXPECT_TRUE(check_unlocked(db_, "t1", "m2", ProgressionOptions{false}).value().unlocked);
}

TEST_F(ProgressionDb, ExplicitAndUnknownPrerequisites) {
  ModuleRecord m4;
  m4.id = "m4";
  m4.prerequisites = std::vector<std::string>{"m1", "m3"};
  ASSERT_TRUE(upsert_module(db_, m4).ok());
  ModuleRecord free;
  free.id = "free";
  free.curriculum_id = "acdr";
  free.position = 99;
  free.prerequisites = std::vector<std::string>{};  // explicitly none
  ASSERT_TRUE(upsert_module(db_, free).ok());
  ModuleRecord orphan;
  orphan.id = "orphan";
  orphan.prerequisites = std::vector<std::string>{"not-registered"};
  ASSERT_TRUE(upsert_module(db_, orphan).ok());

  EXPECT_TRUE(unlocked("t1", "free"));
  EXPECT_FALSE(unlocked("t1", "orphan"));
  EXPECT_NE(check_unlocked(db_, "t1", "orphan").value().reason.find("not registered"),
            std::string::npos);

  for (int i = 0; i < 2; ++i) add_attempt(db_, "t1", "m1", 70, true, minute(i));
  EXPECT_FALSE(unlocked("t1", "m4"));
  for (int i = 0; i < 2; ++i) add_attempt(db_, "t1", "m3", 70, true, minute(10 + i));
  EXPECT_TRUE(unlocked("t1", "m4"));
}

TEST_F(ProgressionDb, TraineeProgressListsTheCurriculumInOrder) {
  for (int i = 0; i < 2; ++i) add_attempt(db_, "t1", "m1", 70, true, minute(i));
  add_attempt(db_, "t1", "m2", 20, false, minute(5));
  DbResult<std::vector<ModuleProgress>> all = trainee_progress(db_, "t1", "acdr");
  ASSERT_TRUE(all.ok()) << all.error().message;
  ASSERT_EQ(all->size(), 3u);
  EXPECT_EQ((*all)[0].module_id, "m1");
  EXPECT_STREQ((*all)[0].state_name(), "mastered");
  EXPECT_STREQ((*all)[1].state_name(), "in progress");
  EXPECT_STREQ((*all)[2].state_name(), "locked");
  EXPECT_EQ((*all)[2].missing_prerequisites, std::vector<std::string>{"m2"});
  EXPECT_FALSE(module_progress(db_, "t1", "nope").ok());
}

}  // namespace
}  // namespace acdr

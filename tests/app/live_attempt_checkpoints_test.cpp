// Tests of app/live_attempt_checkpoints.cpp and LiveAttempt::set_checkpoints: the physics side
// never waits for the writer (a hand-over while it is busy is deferred, and its data goes with
// the next), nothing handed over or staged is lost, a refused checkpoint is carried by the next,
// the sink runs on a thread of its own, and the checkpoints of a live attempt concatenate into
// its record.
#include "app/live_attempt_checkpoints.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <future>
#include <mutex>
#include <thread>

#include "app/live_attempt.hpp"
#include "engine/devices/trajectory.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/app/test_scenes.hpp"

namespace acdr {
namespace {

using namespace std::chrono_literals;

// What a sink was given, call by call (guarded: the sink runs on the writer thread).
struct SinkLog {
  std::mutex mutex;
  std::vector<std::vector<double>> calls;  ///< frame times of each call's new part
  std::vector<double> call_t;              ///< each call's t_s
  std::vector<std::size_t> first_new;      ///< each call's first_new_frame
  std::vector<std::size_t> events;         ///< new events per call
  std::vector<double> bone;                ///< times of the new bone samples, all calls
  std::thread::id thread;

  void add(const CheckpointView& v) {
    std::lock_guard lock(mutex);
    std::vector<double> t;
    for (std::size_t i = v.first_new_frame; i < v.record.frames.size(); ++i)
      t.push_back(v.record.frames[i].t_s);
    calls.push_back(std::move(t));
    call_t.push_back(v.t_s);
    first_new.push_back(v.first_new_frame);
    events.push_back(v.record.events.size() - v.first_new_event);
    for (std::size_t i = v.first_new_bone_sample; i < v.record.bone_loads.size(); ++i)
      bone.push_back(v.record.bone_loads[i].t_s);
    thread = std::this_thread::get_id();
  }
  std::size_t count() {
    std::lock_guard lock(mutex);
    return calls.size();
  }
  /// Waits (up to 5 s) until the sink has been called `n` times.
  bool wait_for(std::size_t n) {
    for (int i = 0; i < 5000 && count() < n; ++i) std::this_thread::sleep_for(1ms);
    return count() >= n;
  }
  std::vector<double> all() {
    std::lock_guard lock(mutex);
    std::vector<double> out;
    for (const auto& c : calls) out.insert(out.end(), c.begin(), c.end());
    return out;
  }
};

void add_frames(AttemptRecording& r, int n) {
  for (int i = 0; i < n; ++i) {
    Frame f;
    f.t_s = static_cast<double>(r.frames.size() + 1) * 1e-3;
    r.frames.push_back(f);
    // A bone load sample every 10 frames, as a scene with the bone model takes them.
    if (r.frames.size() % 10 == 0) {
      BoneLoadRecord& b = r.bone_loads.emplace_back();
      b.t_s = f.t_s;
      b.points.resize(2);
    }
  }
}

TEST(LiveAttemptCheckpoints, ABusyWriterDefersTheHandOverAndNothingIsLost) {
  SinkLog log;
  std::promise<void> entered, release;
  std::shared_future<void> released = release.get_future().share();
  int calls = 0;
  LiveAttemptCheckpoints checkpoints(
      [&](const CheckpointView& v) {
        log.add(v);
        if (++calls == 1) {  // the first write takes long: the writer is busy
          entered.set_value();
          released.wait();
        }
        return true;
      },
      WorldSummary{}, 100);
  checkpoints.start();

  AttemptRecording record;  // the physics thread's record (this thread plays the physics)
  add_frames(record, 100);
  checkpoints.stage(record);
  EXPECT_TRUE(checkpoints.hand_over(0.1));
  entered.get_future().wait();  // the writer took it and is busy writing it
  add_frames(record, 100);
  record.events.push_back(Event{0.15, EventKind::kOverloadWarning, 0.4, "", -1});
  checkpoints.stage(record);
  EXPECT_TRUE(checkpoints.hand_over(0.2));  // waits in the slot
  add_frames(record, 100);
  checkpoints.stage(record);
  // The writer has not taken the previous one: nothing is handed over, nothing waits.
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(checkpoints.hand_over(0.3));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 50ms);
  release.set_value();
  ASSERT_TRUE(log.wait_for(2));  // the writer took the waiting one
  add_frames(record, 50);
  checkpoints.stage(record);
  checkpoints.finish(true);  // the rest, staged since 0.2 s, goes with the flush

  std::vector<double> expected;
  for (const Frame& f : record.frames) expected.push_back(f.t_s);
  EXPECT_EQ(log.all(), expected);
  // The bone's load samples went the same way: each once, in order, none lost.
  std::vector<double> bone;
  for (const BoneLoadRecord& b : record.bone_loads) bone.push_back(b.t_s);
  EXPECT_EQ(bone.size(), 35u);
  EXPECT_EQ(log.bone, bone);
  ASSERT_EQ(log.calls.size(), 3u);
  EXPECT_EQ(log.calls[0].size(), 100u);
  EXPECT_EQ(log.calls[1].size(), 100u);
  EXPECT_EQ(log.calls[2].size(), 150u);
  EXPECT_EQ(log.events, (std::vector<std::size_t>{0, 1, 0}));
  EXPECT_DOUBLE_EQ(log.call_t[1], 0.2);
  EXPECT_DOUBLE_EQ(log.call_t[2], record.frames.back().t_s);
  EXPECT_NE(log.thread, std::this_thread::get_id());
  const LiveCheckpointStats s = checkpoints.stats();
  EXPECT_EQ(s.handed_over, 2);
  EXPECT_EQ(s.deferred, 1);
  EXPECT_EQ(s.saved, 3);
  EXPECT_EQ(s.failed, 0);
  EXPECT_EQ(s.frames_saved, 350);
  EXPECT_EQ(s.largest_frames, 100u);
  EXPECT_GT(s.write_max_ms, 0.0);
}

TEST(LiveAttemptCheckpoints, ARefusedCheckpointIsCarriedByTheNext) {
  SinkLog log;
  int calls = 0;
  LiveAttemptCheckpoints checkpoints(
      [&](const CheckpointView& v) {
        log.add(v);
        return ++calls != 1;  // the store refuses the first
      },
      WorldSummary{}, 10);
  checkpoints.start();
  AttemptRecording record;
  for (int k = 0; k < 2; ++k) {
    add_frames(record, 10);
    checkpoints.stage(record);
    ASSERT_TRUE(checkpoints.hand_over(record.frames.back().t_s));
    // The next hand-over only once the writer has written this one.
    ASSERT_TRUE(log.wait_for(static_cast<std::size_t>(k + 1)));
  }
  checkpoints.finish(false);
  ASSERT_EQ(log.calls.size(), 2u);
  EXPECT_EQ(log.first_new, (std::vector<std::size_t>{0, 0}));  // from the start again
  EXPECT_EQ(log.calls[1].size(), 20u);
  EXPECT_EQ(checkpoints.stats().failed, 1);
  EXPECT_EQ(checkpoints.stats().saved, 1);
  EXPECT_EQ(checkpoints.stats().frames_saved, 20);
}

std::shared_ptr<const ScenarioModel> empty_box() {
  LoadResult loaded = load_scenario_file(test::kSceneData + "empty_box.json");
  EXPECT_TRUE(loaded.ok()) << to_string(loaded.errors);
  return loaded.model;
}

// `seconds` down by 5 mm from the start pose.
Trajectory move_down(const Pose& start, double seconds) {
  std::vector<TrajectorySample> s(2);
  s[0].pose = start;
  s[1].t_s = seconds;
  s[1].pose = start;
  s[1].pose.position.z() -= 0.005;
  return Trajectory(std::move(s));
}

// A live attempt on the empty box whose instrument moves down for `seconds`.
struct LiveRig {
  explicit LiveRig(double seconds)
      : scenario(empty_box()),
        world(scenario->world),
        replay(move_down(scenario->world.instrument_start, seconds)),
        live(*scenario, world, replay) {}
  std::shared_ptr<const ScenarioModel> scenario;
  World world;
  TrajectoryReplay replay;
  LiveAttempt live;
};

// A sink that logs every checkpoint into `log` and saves it.
CheckpointSink logging_sink(SinkLog& log) {
  return [&log](const CheckpointView& v) {
    log.add(v);
    return true;
  };
}

TEST(LiveAttemptCheckpoints, ALiveAttemptCheckpointsOnTheScheduleFromAnotherThread) {
  LiveRig rig(0.45);
  LiveAttempt& live = rig.live;
  SinkLog log;
  live.set_checkpoints(0.1, logging_sink(log));
  live.start();
  const AttemptRun run = live.wait();
  ASSERT_EQ(run.end, AttemptEnd::kInputEnded);
  // Due at 0.1, 0.2, 0.3 and 0.4 s (a hand-over the writer was not ready for goes with the
  // next one); the tail after the last is stored with the attempt, not here.
  const LiveCheckpointStats s = live.checkpoint_stats();
  EXPECT_EQ(s.handed_over + s.deferred, 4);
  ASSERT_GE(s.handed_over, 1);
  ASSERT_EQ(log.call_t.size(), static_cast<std::size_t>(s.handed_over));
  for (double t : log.call_t) {
    const double k = std::round(t / 0.1);
    EXPECT_NEAR(t, 0.1 * k, 1e-9);
    EXPECT_GE(k, 1);
    EXPECT_LE(k, 4);
  }
  EXPECT_NE(log.thread, std::this_thread::get_id());
  const std::vector<double> saved = log.all();
  ASSERT_LE(saved.size(), run.record.frames.size());
  for (std::size_t i = 0; i < saved.size(); ++i) ASSERT_EQ(saved[i], run.record.frames[i].t_s);
  EXPECT_EQ(saved.back(), log.call_t.back());  // a checkpoint ends on its own step
  EXPECT_EQ(s.saved, s.handed_over);
  EXPECT_EQ(s.frames_saved, static_cast<std::int64_t>(saved.size()));
  if (s.deferred == 0) {
    EXPECT_NEAR(log.call_t.back(), 0.4, 1e-9);
  }
}

TEST(LiveAttemptCheckpoints, AnAbandonedLiveAttemptCheckpointsEverythingBeforeItIsClosed) {
  LiveRig rig(2.0);
  LiveAttempt& live = rig.live;
  SinkLog log;
  live.set_checkpoints(0.1, logging_sink(log));
  live.start();
  std::this_thread::sleep_for(250ms);
  live.request_stop(AttemptEnd::kStopped);
  const AttemptRun run = live.wait();
  ASSERT_EQ(run.end, AttemptEnd::kStopped);
  // Everything stepped was checkpointed (the abandoned attempt keeps only that).
  const std::vector<double> saved = log.all();
  ASSERT_EQ(saved.size(), run.record.frames.size());
  for (std::size_t i = 0; i < saved.size(); ++i) ASSERT_EQ(saved[i], run.record.frames[i].t_s);
}

TEST(LiveAttemptCheckpoints, WithoutAnIntervalThereAreNone) {
  LiveRig rig(0.15);
  LiveAttempt& live = rig.live;
  int calls = 0;
  live.set_checkpoints(0.0, [&](const CheckpointView&) { return ++calls > 0; });
  live.start();
  const AttemptRun run = live.wait();
  EXPECT_EQ(run.end, AttemptEnd::kInputEnded);
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(live.checkpoint_stats().handed_over, 0);
}

}  // namespace
}  // namespace acdr

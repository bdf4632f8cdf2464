// Tests of db/outcome_side_file.cpp: a finished attempt whose record cannot be written (another
// connection holds the write lock) is kept in a side file that reads back exactly, is refused
// when damaged, and is stored into the record (then removed) by the next open_store.
#include "db/outcome_side_file.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <stdlib.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include "db/attempt_store.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using test::TempDir;

std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, 8);
  return b;
}

// An outcome with the awkward values: NaN and infinite metrics, a zone event, a recording.
AttemptOutcome awkward_outcome() {
  AttemptOutcome o = test::make_outcome(71.25, true);
  o.metrics.values.emplace_back("blew_up", std::numeric_limits<double>::quiet_NaN());
  o.metrics.values.emplace_back("unbounded", -std::numeric_limits<double>::infinity());
  o.metrics.values.emplace_back("tiny", 4.9e-324);
  o.score.gates = {GateResult{"peak_instrument_force_N", 3.5, 5.0, true}};
  o.score.reasons = {"one", "two, with a comma\nand a line"};
  o.events.push_back(EventRecord{2.5, "force_clamped", "", 4.25, "detail", -1});
  o.events[0].zone_index = 3;
  RecordingData r;
  r.format = "acdr-frames-v2";
  r.frame_count = 1234;
  for (int i = 0; i < 100000; ++i) r.bytes.push_back(static_cast<std::uint8_t>(i * 7 % 251));
  o.recording = r;
  o.duration_s = 9.999;
  o.realtime_factor = 0.3712;
  o.ended_utc = "2026-11-26T09:30:00.123Z";
  return o;
}

void expect_same(const AttemptOutcome& a, const AttemptOutcome& b) {
  ASSERT_EQ(a.metrics.values.size(), b.metrics.values.size());
  for (std::size_t i = 0; i < a.metrics.values.size(); ++i) {
    EXPECT_EQ(a.metrics.values[i].first, b.metrics.values[i].first);
    EXPECT_EQ(bits(a.metrics.values[i].second), bits(b.metrics.values[i].second)) << i;
  }
  EXPECT_EQ(bits(a.score.score), bits(b.score.score));
  EXPECT_EQ(a.score.passed, b.score.passed);
  ASSERT_EQ(a.score.terms.size(), b.score.terms.size());
  for (std::size_t i = 0; i < a.score.terms.size(); ++i) {
    EXPECT_EQ(a.score.terms[i].metric, b.score.terms[i].metric);
    EXPECT_EQ(bits(a.score.terms[i].value), bits(b.score.terms[i].value));
    EXPECT_EQ(bits(a.score.terms[i].score), bits(b.score.terms[i].score));
  }
  ASSERT_EQ(a.score.gates.size(), b.score.gates.size());
  for (std::size_t i = 0; i < a.score.gates.size(); ++i) {
    EXPECT_EQ(a.score.gates[i].metric, b.score.gates[i].metric);
    EXPECT_EQ(bits(a.score.gates[i].max), bits(b.score.gates[i].max));
    EXPECT_EQ(a.score.gates[i].passed, b.score.gates[i].passed);
  }
  EXPECT_EQ(a.score.reasons, b.score.reasons);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (std::size_t i = 0; i < a.events.size(); ++i) {
    EXPECT_EQ(bits(a.events[i].t_s), bits(b.events[i].t_s));
    EXPECT_EQ(a.events[i].kind, b.events[i].kind);
    EXPECT_EQ(a.events[i].zone, b.events[i].zone);
    EXPECT_EQ(bits(a.events[i].value), bits(b.events[i].value));
    EXPECT_EQ(a.events[i].detail, b.events[i].detail);
    EXPECT_EQ(a.events[i].zone_index, b.events[i].zone_index);
  }
  ASSERT_EQ(a.recording.has_value(), b.recording.has_value());
  if (a.recording) {
    EXPECT_EQ(a.recording->format, b.recording->format);
    EXPECT_EQ(a.recording->frame_count, b.recording->frame_count);
    EXPECT_EQ(a.recording->bytes, b.recording->bytes);
  }
  EXPECT_EQ(bits(a.duration_s), bits(b.duration_s));
  EXPECT_EQ(bits(a.realtime_factor), bits(b.realtime_factor));
  EXPECT_EQ(a.ended_utc, b.ended_utc);
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(OutcomeSideFile, ReadsBackExactlyWhatWasWritten) {
  TempDir dir;
  const std::string db = dir.file("record.sqlite");
  const UnsavedOutcome u{17, "0b6d1d6e-1111-4222-8333-444455556666", awkward_outcome()};
  DbResult<std::string> path = write_unsaved_outcome(db, u);
  ASSERT_TRUE(path.ok()) << path.error().message;
  EXPECT_EQ(path.value(), unsaved_outcome_path(db, 17));
  EXPECT_EQ(path.value(), db + ".attempt-17.unsaved");
  DbResult<UnsavedOutcome> back = read_unsaved_outcome(path.value());
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->attempt_id, 17);
  EXPECT_EQ(back->attempt_uuid, u.attempt_uuid);
  expect_same(u.outcome, back->outcome);
  // No temporary file is left behind, and the side file is found by its record.
  EXPECT_EQ(find_unsaved_outcomes(db), std::vector<std::string>{path.value()});
  EXPECT_TRUE(find_unsaved_outcomes(dir.file("other.sqlite")).empty());
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) files += !e.is_directory();
  EXPECT_EQ(files, 1);
}

TEST(OutcomeSideFile, ADamagedOrTruncatedFileIsRefusedNamingIt) {
  TempDir dir;
  const std::string db = dir.file("record.sqlite");
  DbResult<std::string> path = write_unsaved_outcome(db, {3, "u", awkward_outcome()});
  ASSERT_TRUE(path.ok()) << path.error().message;
  const std::string good = file_bytes(path.value());

  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x40;
  std::ofstream(path.value(), std::ios::binary | std::ios::trunc) << flipped;
  DbResult<UnsavedOutcome> a = read_unsaved_outcome(path.value());
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().message.find(path.value()), std::string::npos) << a.error().message;
  EXPECT_NE(a.error().message.find("CRC"), std::string::npos) << a.error().message;

  std::ofstream(path.value(), std::ios::binary | std::ios::trunc) << good.substr(0, 100);
  EXPECT_FALSE(read_unsaved_outcome(path.value()).ok());
  std::ofstream(path.value(), std::ios::binary | std::ios::trunc) << "not a side file";
  DbResult<UnsavedOutcome> c = read_unsaved_outcome(path.value());
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("acdr-unsaved-attempt"), std::string::npos);
  EXPECT_FALSE(read_unsaved_outcome(dir.file("missing")).ok());
}

// A side file left by a program before the real-time factor was kept (format 1: no factor
// after the duration) is still read; the factor is then unknown.
TEST(OutcomeSideFile, AFormatOneFileWithoutTheRealTimeFactorIsStillRead) {
  TempDir dir;
  const std::string db = dir.file("record.sqlite");
  const UnsavedOutcome u{5, "0b6d1d6e-1111-4222-8333-444455556666", awkward_outcome()};
  DbResult<std::string> path = write_unsaved_outcome(db, u);
  ASSERT_TRUE(path.ok()) << path.error().message;
  std::string bytes = file_bytes(path.value());
  // magic, version, attempt id, uuid, end time, duration, then the factor (8 bytes).
  const std::size_t magic = std::strlen("acdr-unsaved-attempt\n");
  const std::size_t factor_at =
      magic + 4 + 8 + 4 + u.attempt_uuid.size() + 4 + u.outcome.ended_utc.size() + 8;
  double stored = 0.0;
  std::memcpy(&stored, bytes.data() + factor_at, 8);
  ASSERT_EQ(stored, u.outcome.realtime_factor);  // the layout this test assumes
  bytes.erase(factor_at, 8);
  bytes[magic] = 1;  // format 1 (little-endian u32)
  bytes.resize(bytes.size() - 4);
  const std::uint32_t crc = static_cast<std::uint32_t>(crc32(
      crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((crc >> (8 * i)) & 0xff));
  std::ofstream(path.value(), std::ios::binary | std::ios::trunc) << bytes;
  DbResult<UnsavedOutcome> back = read_unsaved_outcome(path.value());
  ASSERT_TRUE(back.ok()) << back.error().message;
  AttemptOutcome expected = u.outcome;
  expected.realtime_factor = AttemptOutcome{}.realtime_factor;  // unknown
  expect_same(expected, back->outcome);
}

// Holds the write lock of `path` on a connection of its own (another program, as far as the
// store can tell) until release() or destruction.
class WriteLockHolder {
 public:
  explicit WriteLockHolder(const std::string& path) {
    EXPECT_EQ(sqlite3_open(path.c_str(), &db_), SQLITE_OK);
    EXPECT_EQ(sqlite3_exec(db_, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
  }
  void release() {
    if (db_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_close(db_);
    db_ = nullptr;
  }
  ~WriteLockHolder() { release(); }

 private:
  sqlite3* db_ = nullptr;
};

TEST(OutcomeSideFile, ALockedRecordKeepsTheOutcomeAndTheNextOpenStoresIt) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  std::int64_t id = 0;
  AttemptOutcome outcome = awkward_outcome();
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
    AttemptStart start;
    start.module_id = "m1";
    id = begin_attempt(db, start).value();

    WriteLockHolder lock(path);
    const auto t0 = std::chrono::steady_clock::now();
    const FinalRecord kept = finish_attempt_or_keep(db, id, outcome, 0.4);
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_FALSE(kept.stored);
    EXPECT_NE(kept.error.find("locked"), std::string::npos) << kept.error;
    EXPECT_EQ(kept.side_file, unsaved_outcome_path(path, id));
    EXPECT_GE(waited, 0.35);  // it waited and tried again ...
    EXPECT_LT(waited, 3.0);   // ... for its patience, not the 5 s busy timeout
    ASSERT_TRUE(std::filesystem::exists(kept.side_file));

    // Still locked: the next start cannot store it yet, and says so; the side file stays.
    OpenOptions impatient;
    impatient.busy_timeout_ms = 100;
    DbResult<Database> again = Database::open(path, impatient);
    ASSERT_TRUE(again.ok()) << again.error().message;
    const UnsavedReplay waiting = store_unsaved_outcomes(again.value());
    EXPECT_EQ(waiting.still_pending, std::vector<std::int64_t>{id});
    ASSERT_EQ(waiting.notes.size(), 1u);
    EXPECT_NE(waiting.notes[0].find("still cannot be stored"), std::string::npos)
        << waiting.notes[0];
    EXPECT_TRUE(std::filesystem::exists(kept.side_file));
  }

  // Lock released: the next open_store stores it, says so, and removes the side file.
  std::vector<std::string> notes;
  Database db = test::open_or_fail(path);  // a program without notes also stores it ...
  EXPECT_FALSE(std::filesystem::exists(unsaved_outcome_path(path, id)));
  DbResult<std::optional<AttemptRecord>> a = load_attempt(db, id);
  ASSERT_TRUE(a.ok() && a.value());
  EXPECT_EQ(a.value()->status, AttemptStatus::kCompleted);
  EXPECT_EQ(a.value()->ended_utc, outcome.ended_utc);  // the attempt's end, not the replay's
  EXPECT_EQ(a.value()->duration_s, outcome.duration_s);
  EXPECT_EQ(a.value()->realtime_factor, outcome.realtime_factor);
  EXPECT_EQ(a.value()->score, outcome.score.score);
  EXPECT_EQ(a.value()->passed, true);
  ASSERT_TRUE(a.value()->recording.has_value());
  EXPECT_EQ(a.value()->recording->bytes, outcome.recording->bytes);
  EXPECT_EQ(a.value()->events.size(), outcome.events.size());
  EXPECT_TRUE(std::isnan(*a.value()->metrics.find("blew_up")));
  // ... and one that asks hears about it (nothing left to store now).
  DbResult<Database> quiet = open_store(path, {}, &notes);
  ASSERT_TRUE(quiet.ok());
  EXPECT_TRUE(notes.empty());
}

TEST(OutcomeSideFile, TheNextOpenSaysWhatItStored) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  std::int64_t id = 0;
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
    AttemptStart start;
    start.module_id = "m1";
    id = begin_attempt(db, start).value();
  }
  AttemptOutcome outcome = test::make_outcome(60.0, true);
  outcome.ended_utc = "2026-11-26T09:00:00.000Z";
  ASSERT_TRUE(write_unsaved_outcome(path, {id, "", outcome}).ok());
  // A side file of another record (an attempt this record does not have) is left alone.
  ASSERT_TRUE(write_unsaved_outcome(path, {id + 5, "", outcome}).ok());
  std::vector<std::string> notes;
  DbResult<Database> db = open_store(path, {}, &notes);
  ASSERT_TRUE(db.ok()) << db.error().message;
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find("now stored"), std::string::npos) << notes[0];
  EXPECT_NE(notes[1].find("left in place"), std::string::npos) << notes[1];
  EXPECT_EQ(load_attempt(db.value(), id).value().value().status, AttemptStatus::kCompleted);
  EXPECT_FALSE(std::filesystem::exists(unsaved_outcome_path(path, id)));
  EXPECT_TRUE(std::filesystem::exists(unsaved_outcome_path(path, id + 5)));
}

// When the side file cannot be written next to the database (here: its temporary name is
// taken by a directory; in life: the database's disk is full), it goes to the fallback
// directory ($XDG_STATE_HOME/acdr/unsaved), where the next start finds and stores it too.
TEST(OutcomeSideFile, WhenTheDatabasesDirectoryRefusesItTheFallbackDirectoryKeepsIt) {
  TempDir dir, state;
  const char* old_state = std::getenv("XDG_STATE_HOME");
  const std::string saved_state = old_state ? old_state : "";
  ASSERT_EQ(setenv("XDG_STATE_HOME", state.path().c_str(), 1), 0);
  const std::string path = dir.file("record.sqlite");
  std::int64_t id = 0;
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
    AttemptStart start;
    start.module_id = "m1";
    id = begin_attempt(db, start).value();
  }
  std::filesystem::create_directory(unsaved_outcome_path(path, id) + ".tmp-" +
                                    std::to_string(getpid()));
  AttemptOutcome outcome = test::make_outcome(55.0, true);
  outcome.ended_utc = "2026-11-26T10:00:00.000Z";
  DbResult<std::string> kept = write_unsaved_outcome(path, {id, "", outcome});
  ASSERT_TRUE(kept.ok()) << kept.error().message;
  EXPECT_EQ(std::filesystem::path(kept.value()).parent_path(),
            state.path() / "acdr" / "unsaved");
  EXPECT_EQ(find_unsaved_outcomes(path), std::vector<std::string>{kept.value()});
  EXPECT_TRUE(find_unsaved_outcomes(dir.file("another.sqlite")).empty());

  std::vector<std::string> notes;
  DbResult<Database> db = open_store(path, {}, &notes);
  ASSERT_TRUE(db.ok()) << db.error().message;
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("now stored"), std::string::npos) << notes[0];
  EXPECT_EQ(load_attempt(db.value(), id).value().value().status, AttemptStatus::kCompleted);
  EXPECT_FALSE(std::filesystem::exists(kept.value()));
  if (old_state)
    setenv("XDG_STATE_HOME", saved_state.c_str(), 1);
  else
    unsetenv("XDG_STATE_HOME");
}

}  // namespace
}  // namespace acdr

// Tests of db/writer_identity.cpp: telling a live writer from a gone one.
#include "db/writer_identity.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

namespace acdr {
namespace {

TEST(WriterIdentity, ThisProcessIsAlive) {
  const WriterIdentity self = current_writer();
  EXPECT_EQ(self.pid, static_cast<std::int64_t>(getpid()));
  EXPECT_GT(self.start_ticks, 0);
  EXPECT_NE(self.host.find('/'), std::string::npos);
  EXPECT_EQ(writer_state(self), WriterState::kAlive);
}

TEST(WriterIdentity, OtherHostReusedPidAndNoPidAreGone) {
  WriterIdentity w = current_writer();
  w.host = "elsewhere/other-boot";
  EXPECT_EQ(writer_state(w), WriterState::kGone);
  w = current_writer();
  w.start_ticks += 12345;  // same pid, different process start: pid reused
  EXPECT_EQ(writer_state(w), WriterState::kGone);
  w = current_writer();
  w.pid = 0;
  EXPECT_EQ(writer_state(w), WriterState::kGone);
}

TEST(WriterIdentity, KilledChildIsGoneAsZombieAndOnceReaped) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    for (;;) pause();
  }
  WriterIdentity w = current_writer();
  w.pid = child;
  w.start_ticks = 0;  // unknown start: liveness by pid alone
  EXPECT_EQ(writer_state(w), WriterState::kAlive);
  ASSERT_EQ(kill(child, SIGKILL), 0);
  // Not yet reaped: a zombie, which writes nothing.
  for (int i = 0; i < 200 && writer_state(w) == WriterState::kAlive; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(writer_state(w), WriterState::kGone);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_EQ(writer_state(w), WriterState::kGone);
}

}  // namespace
}  // namespace acdr

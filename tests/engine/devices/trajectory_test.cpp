// Trajectory CSV reading, playback and waypoint interpolation.
#include "engine/devices/trajectory.hpp"

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "engine/devices/waypoint_path.hpp"

namespace acdr {
namespace {

const char* kTwoSamples =
    "# comment\n"
    "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n"
    "0.0,0,0,0,1,0,0,0\n"
    "1.0,0.01,0.02,-0.03,0,0,0,1\n";

TEST(Trajectory, ParsesAndInterpolates) {
  std::string error;
  auto t = Trajectory::parse_csv(kTwoSamples, "mem.csv", &error);
  ASSERT_TRUE(t) << error;
  EXPECT_DOUBLE_EQ(t->duration_s(), 1.0);
  const Pose mid = t->at(0.5);
  EXPECT_NEAR(mid.position.x(), 0.005, 1e-12);
  EXPECT_NEAR(mid.position.z(), -0.015, 1e-12);
  // Half way from identity to a half turn about z is a quarter turn.
  EXPECT_NEAR(Eigen::AngleAxisd(mid.orientation).angle(), M_PI / 2, 1e-9);
  EXPECT_EQ(t->at(-1.0).position, Vec3::Zero());
  EXPECT_NEAR(t->at(5.0).position.y(), 0.02, 1e-12);
}

TEST(Trajectory, ErrorsNameTheLine) {
  std::string error;
  EXPECT_FALSE(Trajectory::parse_csv("t_s,x_m\n", "a.csv", &error));
  EXPECT_NE(error.find("a.csv:1: bad header"), std::string::npos) << error;
  EXPECT_FALSE(Trajectory::parse_csv("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,nan\n", "b.csv",
                                     &error));
  EXPECT_NE(error.find("b.csv:2: field 8"), std::string::npos) << error;
  EXPECT_FALSE(Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n1,0,0,0,1,0,0,0\n0.5,0,0,0,1,0,0,0\n", "c.csv", &error));
  EXPECT_NE(error.find("c.csv:3: time must increase"), std::string::npos) << error;
  EXPECT_FALSE(Trajectory::parse_csv("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0\n", "d.csv",
                                     &error));
  EXPECT_NE(error.find("expected 8 fields"), std::string::npos) << error;
}

const char* kHeader = "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";

TEST(Trajectory, AcceptsOnlyDecimalNumbers) {
  std::string error;
  for (const char* field : {"0x1p-3", "inf", "-inf", "nan", "infinity", "1e", ".", "+", "1.5.2", "0x10"}) {
    SCOPED_TRACE(field);
    const std::string text = std::string(kHeader) + "0,0,0," + field + ",1,0,0,0\n";
    EXPECT_FALSE(Trajectory::parse_csv(text, "h.csv", &error));
    EXPECT_NE(error.find("h.csv:2: field 4 is not a finite number (got '" + std::string(field) + "'"),
              std::string::npos) << error;
  }
  // Every decimal spelling a writer uses is fine.
  auto t = Trajectory::parse_csv(std::string(kHeader) + "0,-1.5e-3,+2,.5,1.,0,0,0E0\n", "ok.csv", &error);
  ASSERT_TRUE(t) << error;
  EXPECT_DOUBLE_EQ(t->samples()[0].pose.position.x(), -1.5e-3);
  EXPECT_DOUBLE_EQ(t->samples()[0].pose.position.z(), 0.5);
  // A value beyond double range is not finite either.
  EXPECT_FALSE(Trajectory::parse_csv(std::string(kHeader) + "0,1e400,0,0,1,0,0,0\n", "o.csv", &error));
  EXPECT_NE(error.find("o.csv:2: field 2 is not a finite number"), std::string::npos) << error;
}

TEST(Trajectory, RefusesAFirstSampleAtNegativeTime) {
  std::string error;
  EXPECT_FALSE(Trajectory::parse_csv(std::string(kHeader) + "-0.5,0,0,0,1,0,0,0\n1,0,0,0,1,0,0,0\n",
                                     "n.csv", &error));
  EXPECT_EQ(error, "n.csv:2: negative time (got -0.5, expected the first sample at t_s >= 0)");
}

TEST(Trajectory, NormalisesQuaternionsOfAnyFiniteScale) {
  // The same quarter turn about z at scales whose squares overflow and underflow.
  const double c = std::sqrt(0.5);
  for (double scale : {1.0, 1e300, 1e-200, 1e-310, 1e308}) {
    SCOPED_TRACE(scale);
    char line[200];
    std::snprintf(line, sizeof line, "0,0,0,0,%.17g,0,0,%.17g\n", c * scale, c * scale);
    std::string error;
    auto t = Trajectory::parse_csv(std::string(kHeader) + line, "q.csv", &error);
    ASSERT_TRUE(t) << error;
    const Quat& q = t->samples()[0].pose.orientation;
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_NEAR(q.w(), c, 1e-15);
    EXPECT_NEAR(q.z(), c, 1e-15);
  }
  std::string error;
  EXPECT_FALSE(Trajectory::parse_csv(std::string(kHeader) + "0,0,0,0,0,0,0,0\n", "z.csv", &error));
  EXPECT_EQ(error, "z.csv:2: zero quaternion (got [0, 0, 0, 0], expected a rotation)");
  EXPECT_FALSE(unit_quaternion(0, 0, 0, 0));
  EXPECT_FALSE(unit_quaternion(1, std::numeric_limits<double>::infinity(), 0, 0));
  EXPECT_FALSE(unit_quaternion(1, std::nan(""), 0, 0));
}

TEST(Trajectory, RefusesADeviceOrFifoInsteadOfAFile) {
  const std::string dir = ::testing::TempDir() + "/acdr_trajectory_files";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::create_symlink("/dev/zero", dir + "/zero.csv");
  std::filesystem::create_symlink("/dev/urandom", dir + "/random.csv");
  ASSERT_EQ(::mkfifo((dir + "/pipe.csv").c_str(), 0600), 0);
  for (const char* name : {"/zero.csv", "/random.csv", "/pipe.csv"}) {
    std::string error;
    EXPECT_FALSE(Trajectory::load_csv(dir + name, &error));
    EXPECT_EQ(error.rfind(dir + name + ": not a regular file (got a ", 0), 0u) << error;
  }
  std::filesystem::remove_all(dir);
}

TEST(Trajectory, SaveLoadRoundTrip) {
  std::string error;
  auto t = Trajectory::parse_csv(kTwoSamples, "mem.csv", &error);
  ASSERT_TRUE(t);
  const std::string path = ::testing::TempDir() + "/roundtrip.csv";
  ASSERT_TRUE(t->save_csv(path, &error)) << error;
  auto back = Trajectory::load_csv(path, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->samples().size(), 2u);
  EXPECT_NEAR(back->samples()[1].pose.position.z(), -0.03, 1e-12);
}

TEST(Trajectory, ReadsAnOptionalGripColumn) {
  std::string error;
  auto t = Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,grip\n0,0,0,0,1,0,0,0,0\n1,0,0,0,1,0,0,0,1\n", "g.csv", &error);
  ASSERT_TRUE(t) << error;
  EXPECT_TRUE(t->has_grip());
  EXPECT_DOUBLE_EQ(t->grip_at(0.25), 0.25);
  EXPECT_DOUBLE_EQ(t->grip_at(5.0), 1.0);
  // Played back, the grip reaches the device sample.
  TrajectoryReplay replay(*t);
  DeviceSample s;
  replay.sample(0.5, s);
  EXPECT_DOUBLE_EQ(s.grip, 0.5);
  // Files without the column read as before: the jaws stay open.
  auto plain = Trajectory::parse_csv(kTwoSamples, "mem.csv", &error);
  ASSERT_TRUE(plain) << error;
  EXPECT_FALSE(plain->has_grip());
  EXPECT_DOUBLE_EQ(plain->grip_at(0.5), 0.0);
  // Saved and loaded again, the column stays.
  const std::string path = ::testing::TempDir() + "/grip.csv";
  ASSERT_TRUE(t->save_csv(path, &error)) << error;
  auto back = Trajectory::load_csv(path, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(back->has_grip());
  EXPECT_DOUBLE_EQ(back->samples()[1].grip, 1.0);
}

TEST(Trajectory, GripErrorsNameFileLineAndValue) {
  std::string error;
  EXPECT_FALSE(Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,grip\n0,0,0,0,1,0,0,0,0\n1,0,0,0,1,0,0,0,1.5\n", "g.csv", &error));
  EXPECT_NE(error.find("g.csv:3: grip out of range (got 1.5, expected 0 (open) to 1 (closed))"),
            std::string::npos)
      << error;
  // A grip value under a header without the column is one field too many.
  EXPECT_FALSE(Trajectory::parse_csv("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0,1\n", "h.csv",
                                     &error));
  EXPECT_NE(error.find("h.csv:2: too many fields (expected 8)"), std::string::npos) << error;
  // The column announced but missing on a row.
  EXPECT_FALSE(Trajectory::parse_csv("t_s,x_m,y_m,z_m,qw,qx,qy,qz,grip\n0,0,0,0,1,0,0,0\n",
                                     "m.csv", &error));
  EXPECT_NE(error.find("m.csv:2: expected 9 fields, got 8"), std::string::npos) << error;
}

TEST(Trajectory, ReadsAnOptionalInstrumentColumnHeldFromSampleToSample) {
  std::string error;
  auto t = Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,grip,instrument\n0,0,0,0,1,0,0,0,0,0\n1,0,0,0,1,0,0,0,1,1\n"
      "2,0,0,0,1,0,0,0,1,0\n",
      "i.csv", &error);
  ASSERT_TRUE(t) << error;
  EXPECT_TRUE(t->has_grip());
  EXPECT_TRUE(t->has_instrument());
  EXPECT_EQ(t->max_instrument(), 1);
  EXPECT_EQ(t->instrument_at(0.5), 0);   // not blended: held until the next sample
  EXPECT_EQ(t->instrument_at(0.999), 0);
  EXPECT_EQ(t->instrument_at(1.0), 1);
  EXPECT_EQ(t->instrument_at(1.5), 1);
  EXPECT_EQ(t->instrument_at(9.0), 0);
  EXPECT_DOUBLE_EQ(t->grip_at(0.5), 0.5);
  TrajectoryReplay replay(*t);
  DeviceSample s;
  replay.sample(1.25, s);
  EXPECT_EQ(s.instrument, 1);
  // Without a grip, the instrument is the ninth field; saved and loaded, the column stays.
  auto only = Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,instrument\n0,0,0,0,1,0,0,0,2\n", "o.csv", &error);
  ASSERT_TRUE(only) << error;
  EXPECT_FALSE(only->has_grip());
  EXPECT_EQ(only->instrument_at(0.0), 2);
  const std::string path = ::testing::TempDir() + "/instrument.csv";
  ASSERT_TRUE(t->save_csv(path, &error)) << error;
  auto back = Trajectory::load_csv(path, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(back->has_instrument());
  EXPECT_EQ(back->samples()[1].instrument, 1);
  // Files without the column ask for no instrument: the one in hand stays.
  auto plain = Trajectory::parse_csv(kTwoSamples, "mem.csv", &error);
  ASSERT_TRUE(plain) << error;
  EXPECT_FALSE(plain->has_instrument());
  EXPECT_EQ(plain->instrument_at(0.5), -1);
  TrajectoryReplay plain_replay(*plain);
  plain_replay.sample(0.5, s);
  EXPECT_EQ(s.instrument, -1);
}

TEST(Trajectory, InstrumentErrorsNameFileLineAndValue) {
  std::string error;
  EXPECT_FALSE(Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,instrument\n0,0,0,0,1,0,0,0,0\n1,0,0,0,1,0,0,0,1.5\n", "i.csv",
      &error));
  EXPECT_NE(error.find("i.csv:3: instrument out of range (got 1.5, expected a whole number 0 to "
                       "255"),
            std::string::npos)
      << error;
  EXPECT_FALSE(Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,instrument\n0,0,0,0,1,0,0,0,-1\n", "n.csv", &error));
  EXPECT_NE(error.find("n.csv:2: instrument out of range (got -1"), std::string::npos) << error;
  // The columns in the other order are not a header.
  EXPECT_FALSE(Trajectory::parse_csv(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,instrument,grip\n0,0,0,0,1,0,0,0,0,0\n", "h.csv", &error));
  EXPECT_NE(error.find("h.csv:1: bad header (got 't_s,x_m,y_m,z_m,qw,qx,qy,qz,instrument,grip', "
                       "expected 't_s,x_m,y_m,z_m,qw,qx,qy,qz' with optional columns ',grip' and "
                       "',instrument' in that order)"),
            std::string::npos)
      << error;
}

TEST(WaypointPath, PassesTheInstrumentThroughFromItsWaypointOn) {
  std::string error;
  auto w = parse_waypoints(
      "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,grip,instrument\n0,0,0,0,0,0,0,0,0\n"
      "1,10,0,0,0,0,0,1,1\n2,10,0,0,0,0,0,1,1\n",
      "w.csv", &error);
  ASSERT_TRUE(w) << error;
  const Trajectory t = sample_waypoints(*w, 1000.0);
  EXPECT_TRUE(t.has_instrument());
  EXPECT_EQ(t.instrument_at(0.5), 0);
  EXPECT_EQ(t.instrument_at(1.0), 1);
  EXPECT_EQ(t.instrument_at(1.7), 1);
  EXPECT_NEAR(t.grip_at(0.5), 0.5, 1e-9);
  auto no_grip = parse_waypoints(
      "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,instrument\n0,0,0,0,0,0,0,1\n", "v.csv",
      &error);
  ASSERT_TRUE(no_grip) << error;
  EXPECT_FALSE(no_grip->has_grip());
  EXPECT_EQ(no_grip->instrument_at(0.0), 1);
}

TEST(WaypointPath, PassesTheGripThroughAlongTheMinimumJerkProfile) {
  std::string error;
  auto w = parse_waypoints(
      "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,grip\n0,0,0,0,0,0,0,0\n1,10,0,0,0,0,0,1\n",
      "w.csv", &error);
  ASSERT_TRUE(w) << error;
  const Trajectory t = sample_waypoints(*w, 1000.0);
  EXPECT_TRUE(t.has_grip());
  EXPECT_NEAR(t.grip_at(0.5), 0.5, 1e-9);     // half way, as the position
  EXPECT_LT(t.grip_at(0.1), 0.1);              // starts slowly
  EXPECT_DOUBLE_EQ(t.grip_at(1.0), 1.0);
  EXPECT_FALSE(parse_waypoints(
      "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,grip\n# c\n0,0,0,0,0,0,0,-0.5\n", "w.csv",
      &error));
  EXPECT_NE(error.find("w.csv:3: grip out of range (got '-0.5'"), std::string::npos) << error;
}

TEST(WaypointPath, MinimumJerkStartsAndStopsAtRest) {
  std::string error;
  auto w = parse_waypoints(
      "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n0,0,0,0,0,0,0\n1,10,0,0,0,0,90\n", "w.csv",
      &error);
  ASSERT_TRUE(w) << error;
  const Trajectory t = sample_waypoints(*w, 1000.0);
  ASSERT_EQ(t.samples().size(), 1001u);
  // Midpoint of a minimum-jerk segment is half way; ends have zero velocity.
  EXPECT_NEAR(t.at(0.5).position.x(), 0.005, 1e-9);
  const double v_start = (t.samples()[1].pose.position.x() - t.samples()[0].pose.position.x()) / 1e-3;
  EXPECT_LT(v_start, 1e-5);
  // Peak speed of minimum jerk is 1.875 * distance / duration (Flash & Hogan 1985).
  double peak = 0;
  for (std::size_t i = 1; i < t.samples().size(); ++i)
    peak = std::max(peak, (t.samples()[i].pose.position - t.samples()[i - 1].pose.position).norm() / 1e-3);
  EXPECT_NEAR(peak, 1.875 * 0.01, 1e-4);
  EXPECT_NEAR(Eigen::AngleAxisd(t.at(1.0).orientation).angle(), M_PI / 2, 1e-9);
}

TEST(WaypointPath, RejectsBadRows) {
  std::string error;
  EXPECT_FALSE(parse_waypoints("t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n0,0,0,0,0,0,0\n0,1,0,0,0,0,0\n",
                               "w.csv", &error));
  EXPECT_NE(error.find("w.csv:3: time must increase"), std::string::npos) << error;
}

}  // namespace
}  // namespace acdr

// Tests of db/utc_time.cpp: the stored time format and xAPI durations.
#include "db/utc_time.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace acdr {
namespace {

TEST(UtcTime, FormatsAndParsesBack) {
  EXPECT_EQ(format_utc(UtcTime{}), "1970-01-01T00:00:00.000Z");
  const UtcTime t = UtcTime{std::chrono::milliseconds(1714555800123)};
  EXPECT_EQ(format_utc(t), "2024-05-01T09:30:00.123Z");
  EXPECT_EQ(parse_utc("2024-05-01T09:30:00.123Z"), std::optional<UtcTime>(t));
  EXPECT_EQ(parse_utc("2024-05-01T09:30:00.123+00:00"), std::optional<UtcTime>(t));
  EXPECT_EQ(parse_utc("2024-05-01T09:30:00Z"),
            std::optional<UtcTime>(t - std::chrono::milliseconds(123)));
  const UtcTime now = utc_now();
  EXPECT_EQ(parse_utc(format_utc(now)), std::optional<UtcTime>(now));
  // Text order is time order.
  EXPECT_LT(format_utc(t), format_utc(t + std::chrono::milliseconds(1)));
}

TEST(UtcTime, RejectsAnythingElse) {
  for (const char* bad : {"", "yesterday", "2024-05-01", "2024-05-01T09:30:00",
                          "2024-05-01T09:30:00.123+02:00", "2024-13-01T09:30:00Z",
                          "2024-02-30T09:30:00Z", "2024-05-01T25:30:00Z", "2024-05-01T09:30:00.Z",
                          "2024-05-01T09:30:00.123Zjunk"}) {
    EXPECT_FALSE(parse_utc(bad).has_value()) << bad;
  }
}

TEST(UtcTime, Iso8601Durations) {
  EXPECT_EQ(iso8601_duration(12.345), "PT12.345S");
  EXPECT_EQ(iso8601_duration(12.3), "PT12.3S");
  EXPECT_EQ(iso8601_duration(12.30049), "PT12.3S");
  EXPECT_EQ(iso8601_duration(60.0), "PT60S");
  EXPECT_EQ(iso8601_duration(0.0005), "PT0.001S");
  EXPECT_EQ(iso8601_duration(0.0), "PT0S");
  EXPECT_EQ(iso8601_duration(-3.0), "PT0S");
  EXPECT_EQ(iso8601_duration(std::nan("")), "PT0S");
}

}  // namespace
}  // namespace acdr

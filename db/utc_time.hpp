// Wall-clock times and durations as the record stores them: UTC ISO 8601 text with
// milliseconds ("2024-05-01T09:30:00.123Z", sorts in time order) and ISO 8601 durations for xAPI
// ("PT12.345S").
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <string_view>

namespace acdr {

using UtcTime = std::chrono::time_point<std::chrono::system_clock, std::chrono::milliseconds>;

/// Now, to the millisecond.
UtcTime utc_now();
/// "YYYY-MM-DDTHH:MM:SS.mmmZ".
std::string format_utc(UtcTime time);
/// format_utc(utc_now()).
std::string utc_now_text();
/// Parses "YYYY-MM-DDTHH:MM:SS[.fff]Z" (what format_utc writes; 'Z' or "+00:00"). nullopt when
/// the text is anything else.
std::optional<UtcTime> parse_utc(std::string_view text);

/// ISO 8601 duration in seconds with millisecond precision: 12.3456 -> "PT12.346S",
/// 0 -> "PT0S". Negative or non-finite input gives "PT0S".
std::string iso8601_duration(double seconds);

}  // namespace acdr

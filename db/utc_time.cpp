// UTC timestamps and ISO 8601 durations: see utc_time.hpp.
#include "db/utc_time.hpp"

#include <cmath>
#include <cstdio>

namespace acdr {

namespace {

bool read_digits(std::string_view text, std::size_t pos, std::size_t count, int& out) {
  if (pos + count > text.size()) return false;
  int value = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const char c = text[pos + i];
    if (c < '0' || c > '9') return false;
    value = value * 10 + (c - '0');
  }
  out = value;
  return true;
}

}  // namespace

UtcTime utc_now() {
  return std::chrono::time_point_cast<std::chrono::milliseconds>(
      std::chrono::system_clock::now());
}

std::string format_utc(UtcTime time) {
  using namespace std::chrono;
  const auto day = floor<days>(time);
  const year_month_day ymd{day};
  const hh_mm_ss<milliseconds> hms{time - day};
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%04d-%02u-%02uT%02d:%02d:%02d.%03dZ",
                static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                static_cast<unsigned>(ymd.day()), static_cast<int>(hms.hours().count()),
                static_cast<int>(hms.minutes().count()), static_cast<int>(hms.seconds().count()),
                static_cast<int>(hms.subseconds().count()));
  return buffer;
}

std::string utc_now_text() { return format_utc(utc_now()); }

std::optional<UtcTime> parse_utc(std::string_view text) {
  using namespace std::chrono;
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, s = 0;
  if (!read_digits(text, 0, 4, y) || text.size() < 20 || text[4] != '-' ||
      !read_digits(text, 5, 2, mo) || text[7] != '-' || !read_digits(text, 8, 2, d) ||
      (text[10] != 'T' && text[10] != ' ') || !read_digits(text, 11, 2, h) || text[13] != ':' ||
      !read_digits(text, 14, 2, mi) || text[16] != ':' || !read_digits(text, 17, 2, s)) {
    return std::nullopt;
  }
  std::size_t pos = 19;
  int millis = 0;
  if (pos < text.size() && text[pos] == '.') {
    // Keep milliseconds, ignore finer digits.
    ++pos;
    int scale = 100;
    std::size_t digits = 0;
    while (pos < text.size() && text[pos] >= '0' && text[pos] <= '9') {
      if (scale > 0) millis += (text[pos] - '0') * scale;
      scale /= 10;
      ++pos;
      ++digits;
    }
    if (digits == 0) return std::nullopt;
  }
  const std::string_view zone = text.substr(pos);
  if (zone != "Z" && zone != "+00:00") return std::nullopt;
  const year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)},
                           day{static_cast<unsigned>(d)}};
  if (!ymd.ok() || h > 23 || mi > 59 || s > 60) return std::nullopt;
  return UtcTime{sys_days{ymd}.time_since_epoch() + hours{h} + minutes{mi} + seconds{s} +
                 milliseconds{millis}};
}

std::string iso8601_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds <= 0.0) return "PT0S";
  const long long millis = std::llround(seconds * 1000.0);
  const long long whole = millis / 1000;
  const long long frac = millis % 1000;
  char buffer[48];
  if (frac == 0) {
    std::snprintf(buffer, sizeof buffer, "PT%lldS", whole);
  } else {
    std::snprintf(buffer, sizeof buffer, "PT%lld.%03lldS", whole, frac);
    // Trim trailing zeros of the fraction: PT12.300S -> PT12.3S.
    std::string text(buffer);
    while (text.size() > 2 && text[text.size() - 2] == '0') text.erase(text.size() - 2, 1);
    return text;
  }
  return buffer;
}

}  // namespace acdr

// CSV trajectories and their playback.
#include "engine/devices/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "engine/core/input_file.hpp"

namespace acdr {
namespace {

constexpr const char* kHeader = "t_s,x_m,y_m,z_m,qw,qx,qy,qz";
constexpr const char* kGripColumn = ",grip";
constexpr const char* kInstrumentColumn = ",instrument";
constexpr int kMostInstruments = 255;  // an instrument index is at most this

std::string format_time(double t) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", t);
  return buf;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

/// A decimal number as CSV writers spell it: [sign] digits [. digits] [e [sign] digits], with
/// at least one digit before the exponent. strtod alone would also take hexadecimal ("0x1p-3"),
/// "inf" and "nan", which no trajectory writer produces on purpose.
bool is_decimal_number(const std::string& f) {
  std::size_t i = 0;
  const std::size_t n = f.size();
  auto digits = [&] {
    const std::size_t from = i;
    while (i < n && f[i] >= '0' && f[i] <= '9') ++i;
    return i - from;
  };
  if (i < n && (f[i] == '+' || f[i] == '-')) ++i;
  std::size_t mantissa = digits();
  if (i < n && f[i] == '.') {
    ++i;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (i < n && (f[i] == 'e' || f[i] == 'E')) {
    ++i;
    if (i < n && (f[i] == '+' || f[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  return i == n;
}

}  // namespace

std::optional<Quat> unit_quaternion(double w, double x, double y, double z) {
  if (!std::isfinite(w) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return std::nullopt;
  const double m = std::max({std::fabs(w), std::fabs(x), std::fabs(y), std::fabs(z)});
  if (!(m > 0.0)) return std::nullopt;
  // A device's quaternion is near unit length: normalised as it is, so recorded trajectories
  // replay to the same bits. Only an extreme scale is divided out first, so neither 1e300
  // (whose square overflows) nor 1e-200 (whose square underflows to zero) loses the direction.
  const bool ordinary = m > 1e-100 && m < 1e100;
  Quat q = ordinary ? Quat(w, x, y, z) : Quat(w / m, x / m, y / m, z / m);
  q.normalize();
  return q;
}

Trajectory::Trajectory(std::vector<TrajectorySample> samples, bool has_grip, bool has_instrument)
    : samples_(std::move(samples)), has_grip_(has_grip), has_instrument_(has_instrument) {}

std::optional<Trajectory> Trajectory::load_csv(const std::string& path, std::string* error) {
  std::string why;
  const auto text = read_input_file(path, kMaxTrajectoryFileBytes, "a trajectory file (CSV)", &why);
  if (!text) {
    if (error) *error = path + ": " + why;
    return std::nullopt;
  }
  return parse_csv(*text, path, error);
}

std::optional<Trajectory> Trajectory::parse_csv(const std::string& text, const std::string& name,
                                                std::string* error) {
  auto fail = [&](int line, const std::string& what) {
    if (error) *error = name + ":" + std::to_string(line) + ": " + what;
    return std::nullopt;
  };
  std::vector<TrajectorySample> samples;
  std::istringstream lines(text);
  std::string raw;
  int line_no = 0;
  bool header_seen = false;
  int fields_expected = 8;
  bool has_grip = false, has_instrument = false;
  while (std::getline(lines, raw)) {
    ++line_no;
    const std::string line = trim(raw);
    if (line.empty() || line[0] == '#') continue;
    if (!header_seen) {
      std::string compact;
      for (char ch : line)
        if (ch != ' ') compact += ch;
      const std::string base = kHeader;
      const std::string grip_col = kGripColumn, instrument_col = kInstrumentColumn;
      if (compact == base) {
      } else if (compact == base + grip_col) {
        has_grip = true;
      } else if (compact == base + instrument_col) {
        has_instrument = true;
      } else if (compact == base + grip_col + instrument_col) {
        has_grip = has_instrument = true;
      } else {
        return fail(line_no, "bad header (got '" + line + "', expected '" + kHeader +
                                 "' with optional columns ',grip' and ',instrument' in that order)");
      }
      fields_expected = 8 + (has_grip ? 1 : 0) + (has_instrument ? 1 : 0);
      header_seen = true;
      continue;
    }
    // Eight comma-separated finite numbers, and the grip and the instrument when present.
    double v[10];
    std::istringstream fields(line);
    std::string field;
    int count = 0;
    while (std::getline(fields, field, ',')) {
      if (count >= fields_expected)
        return fail(line_no, "too many fields (expected " + std::to_string(fields_expected) + ")");
      const std::string f = trim(field);
      char* end = nullptr;
      v[count] = is_decimal_number(f) ? std::strtod(f.c_str(), &end) : 0.0;
      if (end != f.c_str() + f.size() || !std::isfinite(v[count]))
        return fail(line_no, "field " + std::to_string(count + 1) + " is not a finite number (got '" +
                                 f.substr(0, 40) + "', expected a decimal number such as 0.25 or -1.5e-3)");
      ++count;
    }
    if (count != fields_expected)
      return fail(line_no, "expected " + std::to_string(fields_expected) + " fields, got " +
                               std::to_string(count));
    const double grip = has_grip ? v[8] : 0.0;
    if (!(grip >= 0.0 && grip <= 1.0))
      return fail(line_no, "grip out of range (got " + format_time(grip) +
                               ", expected 0 (open) to 1 (closed))");
    const double tool = has_instrument ? v[has_grip ? 9 : 8] : -1.0;
    if (has_instrument && !(tool >= 0.0 && tool <= kMostInstruments && tool == std::floor(tool)))
      return fail(line_no, "instrument out of range (got " + format_time(tool) +
                               ", expected a whole number 0 to 255: the place of the instrument "
                               "in the scene's instruments, 0 the first)");
    if (samples.empty() && v[0] < 0.0)
      return fail(line_no, "negative time (got " + format_time(v[0]) +
                               ", expected the first sample at t_s >= 0)");
    if (!samples.empty() && !(v[0] > samples.back().t_s))
      return fail(line_no, "time must increase (got " + format_time(v[0]) + " after " +
                               format_time(samples.back().t_s) + ")");
    const std::optional<Quat> q = unit_quaternion(v[4], v[5], v[6], v[7]);
    if (!q) return fail(line_no, "zero quaternion (got [0, 0, 0, 0], expected a rotation)");
    samples.push_back({v[0], Pose{Vec3(v[1], v[2], v[3]), *q}, grip, static_cast<int>(tool)});
  }
  if (!header_seen) return fail(line_no, std::string("missing header (expected '") + kHeader + "')");
  if (samples.empty()) return fail(line_no, "no samples (expected at least one)");
  return Trajectory(std::move(samples), has_grip, has_instrument);
}

bool Trajectory::save_csv(const std::string& path, std::string* error) const {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    if (error) *error = path + ": cannot write trajectory file";
    return false;
  }
  std::fprintf(f, "# ACDR Trainer device trajectory: grip pose over time, SI units\n%s%s%s\n",
               kHeader, has_grip_ ? kGripColumn : "", has_instrument_ ? kInstrumentColumn : "");
  for (const auto& s : samples_) {
    const auto& p = s.pose.position;
    const auto& q = s.pose.orientation;
    std::fprintf(f, "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", s.t_s, p.x(), p.y(), p.z(), q.w(),
                 q.x(), q.y(), q.z());
    if (has_grip_) std::fprintf(f, ",%.6g", s.grip);
    if (has_instrument_) std::fprintf(f, ",%d", s.instrument);
    std::fputc('\n', f);
  }
  const bool ok = std::fclose(f) == 0;
  if (!ok && error) *error = path + ": write failed";
  return ok;
}

std::pair<std::size_t, double> Trajectory::segment(double t_s) const {
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t_s,
                                   [](double t, const TrajectorySample& s) { return t < s.t_s; });
  const auto& b = *it;
  const auto& a = *(it - 1);
  return {static_cast<std::size_t>(it - samples_.begin()), (t_s - a.t_s) / (b.t_s - a.t_s)};
}

Pose Trajectory::at(double t_s) const {
  if (samples_.empty()) return Pose{};
  if (t_s <= samples_.front().t_s) return samples_.front().pose;
  if (t_s >= samples_.back().t_s) return samples_.back().pose;
  const auto [ib, u] = segment(t_s);
  const auto& a = samples_[ib - 1];
  const auto& b = samples_[ib];
  Pose p;
  p.position = a.pose.position + u * (b.pose.position - a.pose.position);
  p.orientation = a.pose.orientation.slerp(u, b.pose.orientation);
  return p;
}

double Trajectory::grip_at(double t_s) const {
  if (samples_.empty()) return 0.0;
  if (t_s <= samples_.front().t_s) return samples_.front().grip;
  if (t_s >= samples_.back().t_s) return samples_.back().grip;
  const auto [ib, u] = segment(t_s);
  return samples_[ib - 1].grip + u * (samples_[ib].grip - samples_[ib - 1].grip);
}

int Trajectory::instrument_at(double t_s) const {
  if (samples_.empty() || !has_instrument_) return -1;
  if (t_s <= samples_.front().t_s) return samples_.front().instrument;
  if (t_s >= samples_.back().t_s) return samples_.back().instrument;
  const auto [ib, u] = segment(t_s);
  return samples_[ib - 1].instrument;
}

int Trajectory::max_instrument() const {
  int most = -1;
  for (const TrajectorySample& s : samples_) most = std::max(most, s.instrument);
  return most;
}

bool TrajectoryReplay::sample(double t_s, DeviceSample& out) {
  out.t_s = t_s;
  out.pose = trajectory_.at(t_s);
  out.grip = trajectory_.grip_at(t_s);
  out.instrument = trajectory_.instrument_at(t_s);
  out.buttons = 0;
  out.end = t_s >= trajectory_.duration_s();
  return true;
}

}  // namespace acdr

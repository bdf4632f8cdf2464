// Minimum-jerk interpolation of waypoints.
#include "engine/devices/waypoint_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

namespace acdr {
namespace {

constexpr const char* kHeader = "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg";


double minimum_jerk(double u) { return u * u * u * (10.0 + u * (-15.0 + 6.0 * u)); }

}  // namespace

Quat quat_from_rpy_deg(double roll, double pitch, double yaw) {
  const double k = std::numbers::pi / 180.0;
  return Quat(Eigen::AngleAxisd(yaw * k, Vec3::UnitZ()) *
              Eigen::AngleAxisd(pitch * k, Vec3::UnitY()) *
              Eigen::AngleAxisd(roll * k, Vec3::UnitX()));
}

std::optional<Trajectory> parse_waypoints(const std::string& text, const std::string& name,
                                          std::string* error) {
  // Reuse the trajectory reader's checks by translating each row into SI first.
  std::istringstream lines(text);
  std::ostringstream si;
  std::string line;
  int line_no = 0;
  bool header_seen = false;
  int fields_expected = 7;
  bool has_grip = false, has_instrument = false;
  double last_t = -1e300;
  auto fail = [&](const std::string& what) {
    if (error) *error = name + ":" + std::to_string(line_no) + ": " + what;
    return std::nullopt;
  };
  while (std::getline(lines, line)) {
    ++line_no;
    std::string compact;
    for (char ch : line)
      if (ch != ' ' && ch != '\t' && ch != '\r') compact += ch;
    if (compact.empty() || compact[0] == '#') continue;
    if (!header_seen) {
      const std::string base = kHeader;
      if (compact == base) {
      } else if (compact == base + ",grip") {
        has_grip = true;
      } else if (compact == base + ",instrument") {
        has_instrument = true;
      } else if (compact == base + ",grip,instrument") {
        has_grip = has_instrument = true;
      } else {
        return fail("bad header (got '" + compact + "', expected '" + kHeader +
                    "' with optional columns ',grip' and ',instrument' in that order)");
      }
      // The grip and instrument columns pass through to the trajectory's (checked there).
      fields_expected = 7 + (has_grip ? 1 : 0) + (has_instrument ? 1 : 0);
      si << "t_s,x_m,y_m,z_m,qw,qx,qy,qz" << (has_grip ? ",grip" : "")
         << (has_instrument ? ",instrument" : "") << "\n";
      header_seen = true;
      continue;
    }
    double v[9];
    std::istringstream fields(compact);
    std::string field;
    int count = 0;
    while (std::getline(fields, field, ',')) {
      if (count >= fields_expected)
        return fail("too many fields (expected " + std::to_string(fields_expected) + ")");
      char* end = nullptr;
      v[count] = std::strtod(field.c_str(), &end);
      if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(v[count]))
        return fail("field " + std::to_string(count + 1) + " is not a finite number (got '" +
                    field + "')");
      ++count;
    }
    if (count != fields_expected)
      return fail("expected " + std::to_string(fields_expected) + " fields, got " +
                  std::to_string(count));
    if (!(v[0] > last_t))
      return fail("time must increase (got " + std::to_string(v[0]) + " after " +
                  std::to_string(last_t) + ")");
    last_t = v[0];
    if (has_grip && !(v[7] >= 0.0 && v[7] <= 1.0))
      return fail("grip out of range (got '" + field + "', expected 0 (open) to 1 (closed))");
    const Quat q = quat_from_rpy_deg(v[4], v[5], v[6]);
    char row[256];
    std::snprintf(row, sizeof row, "%.9g,%.9g,%.9g,%.9g,%.17g,%.17g,%.17g,%.17g", v[0],
                  v[1] * 1e-3, v[2] * 1e-3, v[3] * 1e-3, q.w(), q.x(), q.y(), q.z());
    si << row;
    for (int c = 7; c < fields_expected; ++c) {
      std::snprintf(row, sizeof row, ",%.17g", v[c]);
      si << row;
    }
    si << '\n';
  }
  if (!header_seen) return fail(std::string("missing header (expected '") + kHeader + "')");
  return Trajectory::parse_csv(si.str(), name + " (converted)", error);
}

Trajectory sample_waypoints(const Trajectory& waypoints, double rate_hz) {
  const auto& w = waypoints.samples();
  std::vector<TrajectorySample> out;
  if (w.empty()) return Trajectory(out, waypoints.has_grip(), waypoints.has_instrument());
  const double dt = 1.0 / rate_hz;
  const double t0 = w.front().t_s;
  const double t1 = w.back().t_s;
  const auto steps = static_cast<std::size_t>(std::floor((t1 - t0) / dt + 1e-9));
  out.reserve(steps + 2);
  std::size_t seg = 0;
  for (std::size_t i = 0; i <= steps; ++i) {
    const double t = t0 + static_cast<double>(i) * dt;
    while (seg + 2 < w.size() && t > w[seg + 1].t_s) ++seg;
    const auto& a = w[seg];
    const auto& b = w[std::min(seg + 1, w.size() - 1)];
    const double span = b.t_s - a.t_s;
    const double u = span > 0.0 ? std::clamp((t - a.t_s) / span, 0.0, 1.0) : 1.0;
    const double s = minimum_jerk(u);
    Pose p;
    p.position = a.pose.position + s * (b.pose.position - a.pose.position);
    p.orientation = a.pose.orientation.slerp(s, b.pose.orientation).normalized();
    // The instrument is asked for from its waypoint on, not blended.
    out.push_back({t, p, a.grip + s * (b.grip - a.grip), u >= 1.0 ? b.instrument : a.instrument});
  }
  if (out.back().t_s < t1 - 1e-12)
    out.push_back({t1, w.back().pose, w.back().grip, w.back().instrument});
  return Trajectory(std::move(out), waypoints.has_grip(), waypoints.has_instrument());
}

}  // namespace acdr

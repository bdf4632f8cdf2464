// CSV trajectories and their playback.
#include "engine/devices/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace acdr {
namespace {

constexpr const char* kHeader = "t_s,x_m,y_m,z_m,qw,qx,qy,qz";

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

}  // namespace

Trajectory::Trajectory(std::vector<TrajectorySample> samples) : samples_(std::move(samples)) {}

std::optional<Trajectory> Trajectory::load_csv(const std::string& path, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (error) *error = path + ": cannot open trajectory file";
    return std::nullopt;
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_csv(buffer.str(), path, error);
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
  while (std::getline(lines, raw)) {
    ++line_no;
    const std::string line = trim(raw);
    if (line.empty() || line[0] == '#') continue;
    if (!header_seen) {
      std::string compact;
      for (char ch : line)
        if (ch != ' ') compact += ch;
      if (compact != kHeader)
        return fail(line_no, "bad header (got '" + line + "', expected '" + kHeader + "')");
      header_seen = true;
      continue;
    }
    // Eight comma-separated finite numbers.
    double v[8];
    std::istringstream fields(line);
    std::string field;
    int count = 0;
    while (std::getline(fields, field, ',')) {
      if (count >= 8) return fail(line_no, "too many fields (expected 8)");
      const std::string f = trim(field);
      char* end = nullptr;
      v[count] = std::strtod(f.c_str(), &end);
      if (f.empty() || end != f.c_str() + f.size() || !std::isfinite(v[count]))
        return fail(line_no, "field " + std::to_string(count + 1) + " is not a finite number (got '" +
                                 f + "')");
      ++count;
    }
    if (count != 8)
      return fail(line_no, "expected 8 fields, got " + std::to_string(count));
    if (!samples.empty() && !(v[0] > samples.back().t_s))
      return fail(line_no, "time must increase (got " + std::to_string(v[0]) + " after " +
                               std::to_string(samples.back().t_s) + ")");
    Quat q(v[4], v[5], v[6], v[7]);
    if (q.norm() < 1e-9) return fail(line_no, "zero quaternion (expected a rotation)");
    q.normalize();
    samples.push_back({v[0], Pose{Vec3(v[1], v[2], v[3]), q}});
  }
  if (!header_seen) return fail(line_no, std::string("missing header (expected '") + kHeader + "')");
  if (samples.empty()) return fail(line_no, "no samples (expected at least one)");
  return Trajectory(std::move(samples));
}

bool Trajectory::save_csv(const std::string& path, std::string* error) const {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    if (error) *error = path + ": cannot write trajectory file";
    return false;
  }
  std::fprintf(f, "# ACDR Trainer device trajectory: grip pose over time, SI units\n%s\n", kHeader);
  for (const auto& s : samples_) {
    const auto& p = s.pose.position;
    const auto& q = s.pose.orientation;
    std::fprintf(f, "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", s.t_s, p.x(), p.y(), p.z(), q.w(),
                 q.x(), q.y(), q.z());
  }
  const bool ok = std::fclose(f) == 0;
  if (!ok && error) *error = path + ": write failed";
  return ok;
}

Pose Trajectory::at(double t_s) const {
  if (samples_.empty()) return Pose{};
  if (t_s <= samples_.front().t_s) return samples_.front().pose;
  if (t_s >= samples_.back().t_s) return samples_.back().pose;
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t_s,
                                   [](double t, const TrajectorySample& s) { return t < s.t_s; });
  const auto& b = *it;
  const auto& a = *(it - 1);
  const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  Pose p;
  p.position = a.pose.position + u * (b.pose.position - a.pose.position);
  p.orientation = a.pose.orientation.slerp(u, b.pose.orientation);
  return p;
}

bool TrajectoryReplay::sample(double t_s, DeviceSample& out) {
  out.t_s = t_s;
  out.pose = trajectory_.at(t_s);
  out.buttons = 0;
  out.end = t_s >= trajectory_.duration_s();
  return true;
}

}  // namespace acdr

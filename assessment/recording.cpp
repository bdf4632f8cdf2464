// Recording encoder and decoder.
#include "assessment/recording.hpp"

#include <cstring>

namespace acdr {
namespace {

constexpr char kMagic[8] = {'A', 'C', 'D', 'R', 'R', 'E', 'C', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint64_t kMaxCount = 1ull << 28;  // refuses absurd counts from damaged data

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put_vec(const Vec3& v) { put(v.x()), put(v.y()), put(v.z()); }
  void put_pose(const Pose& p) {
    put_vec(p.position);
    put(p.orientation.w()), put(p.orientation.x()), put(p.orientation.y()),
        put(p.orientation.z());
  }
  std::vector<std::uint8_t> bytes;
};

class Reader {
 public:
  explicit Reader(const std::vector<std::uint8_t>& b) : bytes(b) {}
  template <typename T>
  bool get(T& v) {
    if (pos + sizeof(T) > bytes.size()) return false;
    std::memcpy(&v, bytes.data() + pos, sizeof(T));
    pos += sizeof(T);
    return true;
  }
  bool get_vec(Vec3& v) { return get(v.x()) && get(v.y()) && get(v.z()); }
  bool get_pose(Pose& p) {
    double w, x, y, z;
    if (!get_vec(p.position) || !get(w) || !get(x) || !get(y) || !get(z)) return false;
    p.orientation = Quat(w, x, y, z);
    return true;
  }
  const std::vector<std::uint8_t>& bytes;
  std::size_t pos = 0;
};

}  // namespace

std::vector<std::uint8_t> encode_recording(const AttemptRecording& r) {
  Writer w;
  w.bytes.insert(w.bytes.end(), kMagic, kMagic + 8);
  w.put(kVersion);
  const WorldSummary& s = r.summary;
  w.put(s.dt_s), w.put(s.particle_volume_m3), w.put(s.initial_target), w.put(s.initial_protected);
  w.put(s.yield_moment_Nm), w.put(s.warning_moment_Nm), w.put(s.device_max_force_N);
  w.put(static_cast<std::uint64_t>(r.frames.size()));
  for (const Frame& f : r.frames) {
    w.put(f.t_s);
    w.put_pose(f.device);
    w.put_pose(f.instrument);
    w.put_vec(f.tip_m);
    w.put_vec(f.coupling_force_N);
    w.put_vec(f.feedback_force_N);
    w.put_vec(f.nucleus_force_N);
    w.put_vec(f.contact_force_N);
    w.put(f.bending_moment_Nm);
    w.put(f.removed_target), w.put(f.removed_protected), w.put(f.broken_bonds);
    w.put(f.active_particles), w.put(f.solver_iterations);
    w.put(static_cast<std::uint8_t>(f.input_valid));
  }
  w.put(static_cast<std::uint64_t>(r.events.size()));
  for (const Event& e : r.events) {
    w.put(e.t_s);
    w.put(static_cast<std::uint8_t>(e.kind));
    w.put(e.value);
    w.put(static_cast<std::uint32_t>(e.detail.size()));
    w.bytes.insert(w.bytes.end(), e.detail.begin(), e.detail.end());
  }

  return std::move(w.bytes);
}

std::optional<AttemptRecording> decode_recording(const std::vector<std::uint8_t>& bytes,
                                              std::string* error) {
  auto fail = [&](const char* why) {
    if (error) *error = std::string("recording: ") + why;
    return std::nullopt;
  };
  Reader rd(bytes);
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
    return fail("not an ACDR recording");
  rd.pos = 8;
  std::uint32_t version = 0;
  if (!rd.get(version) || version != kVersion) return fail("unknown recording version");
  AttemptRecording r;
  WorldSummary& s = r.summary;
  if (!(rd.get(s.dt_s) && rd.get(s.particle_volume_m3) && rd.get(s.initial_target) &&
        rd.get(s.initial_protected) && rd.get(s.yield_moment_Nm) && rd.get(s.warning_moment_Nm) &&
        rd.get(s.device_max_force_N)))
    return fail("truncated summary");
  std::uint64_t n = 0;
  if (!rd.get(n) || n > kMaxCount) return fail("bad frame count");
  r.frames.resize(n);
  for (Frame& f : r.frames) {
    std::uint8_t valid = 0;
    if (!(rd.get(f.t_s) && rd.get_pose(f.device) && rd.get_pose(f.instrument) &&
          rd.get_vec(f.tip_m) && rd.get_vec(f.coupling_force_N) &&
          rd.get_vec(f.feedback_force_N) && rd.get_vec(f.nucleus_force_N) &&
          rd.get_vec(f.contact_force_N) && rd.get(f.bending_moment_Nm) &&
          rd.get(f.removed_target) && rd.get(f.removed_protected) && rd.get(f.broken_bonds) &&
          rd.get(f.active_particles) && rd.get(f.solver_iterations) && rd.get(valid)))
      return fail("truncated frames");
    f.input_valid = valid != 0;
  }
  if (!rd.get(n) || n > kMaxCount) return fail("bad event count");
  r.events.resize(n);
  for (Event& e : r.events) {
    std::uint8_t kind = 0;
    std::uint32_t len32 = 0;
    if (!(rd.get(e.t_s) && rd.get(kind) && rd.get(e.value) && rd.get(len32)))
      return fail("truncated events");
    if (kind > static_cast<std::uint8_t>(kLastEventKind)) return fail("unknown event");
    if (rd.pos + len32 > bytes.size()) return fail("truncated event text");
    e.kind = static_cast<EventKind>(kind);
    e.detail.assign(reinterpret_cast<const char*>(bytes.data() + rd.pos), len32);
    rd.pos += len32;
  }
  if (rd.pos != bytes.size()) return fail("trailing bytes");
  return r;
}

}  // namespace acdr

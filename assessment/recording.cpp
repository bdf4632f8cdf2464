// Recording encoder and decoder (layouts in recording.hpp).
#include "assessment/recording.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

namespace acdr {
namespace {

constexpr char kMagicV1[8] = {'A', 'C', 'D', 'R', 'R', 'E', 'C', '1'};
constexpr char kMagicV2[8] = {'A', 'C', 'D', 'R', 'R', 'E', 'C', '2'};
constexpr std::uint64_t kMaxCount = 1ull << 28;  // refuses absurd counts from damaged data
constexpr std::uint8_t kFramesTag = 'F';
constexpr std::uint8_t kEventsTag = 'E';
constexpr std::uint8_t kBoneLoadsTag = 'B';
constexpr std::uint8_t kRemovedTag = 'R';

static_assert(std::endian::native == std::endian::little,
              "recordings are little-endian; a big-endian port needs byte swaps here");

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : bytes(out) {}
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
  void put_text(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  std::vector<std::uint8_t>& bytes;
};

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <typename T>
  bool get(T& v) {
    if (pos + sizeof(T) > size_) return false;
    std::memcpy(&v, data_ + pos, sizeof(T));
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
  bool get_text(std::string& s) {
    std::uint32_t n = 0;
    if (!get(n) || pos + n > size_) return false;
    s.assign(reinterpret_cast<const char*>(data_ + pos), n);
    pos += n;
    return true;
  }
  bool skip(std::size_t n) {
    if (pos + n > size_) return false;
    pos += n;
    return true;
  }
  const std::uint8_t* here() const { return data_ + pos; }
  std::size_t left() const { return size_ - pos; }
  std::size_t pos = 0;

 private:
  const std::uint8_t* data_;
  std::size_t size_;
};

// --- columns ---------------------------------------------------------------------------------
// The frame fields by type, in the order they are stored. Getters take a mutable frame so one
// table serves both directions; the encoder only reads through them.
using F64Field = double& (*)(Frame&);
using I32Field = std::int32_t& (*)(Frame&);

// The force sent to the device is not here: unless clamped or rate-limited it is exactly minus
// the coupling force, so it is stored after these as the XOR of the two bit patterns (then a
// constant sign bit, which compresses to almost nothing; lossless either way).
const F64Field kF64Fields[] = {
    [](Frame& f) -> double& { return f.t_s; },
    [](Frame& f) -> double& { return f.device.position.x(); },
    [](Frame& f) -> double& { return f.device.position.y(); },
    [](Frame& f) -> double& { return f.device.position.z(); },
    [](Frame& f) -> double& { return f.device.orientation.w(); },
    [](Frame& f) -> double& { return f.device.orientation.x(); },
    [](Frame& f) -> double& { return f.device.orientation.y(); },
    [](Frame& f) -> double& { return f.device.orientation.z(); },
    [](Frame& f) -> double& { return f.instrument.position.x(); },
    [](Frame& f) -> double& { return f.instrument.position.y(); },
    [](Frame& f) -> double& { return f.instrument.position.z(); },
    [](Frame& f) -> double& { return f.instrument.orientation.w(); },
    [](Frame& f) -> double& { return f.instrument.orientation.x(); },
    [](Frame& f) -> double& { return f.instrument.orientation.y(); },
    [](Frame& f) -> double& { return f.instrument.orientation.z(); },
    [](Frame& f) -> double& { return f.tip_m.x(); },
    [](Frame& f) -> double& { return f.tip_m.y(); },
    [](Frame& f) -> double& { return f.tip_m.z(); },
    [](Frame& f) -> double& { return f.coupling_force_N.x(); },
    [](Frame& f) -> double& { return f.coupling_force_N.y(); },
    [](Frame& f) -> double& { return f.coupling_force_N.z(); },
    [](Frame& f) -> double& { return f.nucleus_force_N.x(); },
    [](Frame& f) -> double& { return f.nucleus_force_N.y(); },
    [](Frame& f) -> double& { return f.nucleus_force_N.z(); },
    [](Frame& f) -> double& { return f.contact_force_N.x(); },
    [](Frame& f) -> double& { return f.contact_force_N.y(); },
    [](Frame& f) -> double& { return f.contact_force_N.z(); },
    [](Frame& f) -> double& { return f.bending_moment_Nm; },
};

const I32Field kI32Fields[] = {
    [](Frame& f) -> std::int32_t& { return f.removed_target; },
    [](Frame& f) -> std::int32_t& { return f.removed_protected; },
    [](Frame& f) -> std::int32_t& { return f.broken_bonds; },
    [](Frame& f) -> std::int32_t& { return f.active_particles; },
    [](Frame& f) -> std::int32_t& { return f.solver_iterations; },
    [](Frame& f) -> std::int32_t& { return f.zone_count; },
};

template <typename U>
U zigzag(U delta) {
  using S = std::make_signed_t<U>;
  const S s = static_cast<S>(delta);
  return static_cast<U>((static_cast<U>(s) << 1) ^ static_cast<U>(s >> (sizeof(U) * 8 - 1)));
}
template <typename U>
U unzigzag(U z) {
  return static_cast<U>((z >> 1) ^ (~(z & 1) + 1));
}

// Residual of value i under a predictor of order 1 (the previous value) or 2 (linear
// extrapolation from the two previous), on bit patterns with wrap-around.
template <typename U>
U predicted(const U* v, std::size_t i, int order) {
  const U p1 = i >= 1 ? v[i - 1] : 0;
  if (order == 1) return p1;
  const U p2 = i >= 2 ? v[i - 2] : 0;
  return static_cast<U>(2 * p1 - p2);
}

// Bytes needed for the residuals (the leading zero bytes cost nearly nothing after zlib): how
// the encoder picks the predictor of a column.
template <typename U>
std::size_t residual_bytes(const std::vector<U>& v, int order) {
  std::size_t total = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const U r = zigzag(static_cast<U>(v[i] - predicted(v.data(), i, order)));
    total += (sizeof(U) * 8 - static_cast<std::size_t>(std::countl_zero(r)) + 7) / 8;
  }
  return total;
}

// Writes n unsigned values (bit patterns): u8 predictor order, then the zigzag-coded residuals
// byte-shuffled (all lowest bytes, then all next bytes, ...). Smooth signals (poses) predict
// best linearly, noisy ones (forces) from the previous value. `scratch` holds n.
template <typename U>
void put_column(const std::vector<U>& values, std::vector<U>& scratch,
                std::vector<std::uint8_t>& out) {
  const std::size_t n = values.size();
  const int order = residual_bytes(values, 2) < residual_bytes(values, 1) ? 2 : 1;
  out.push_back(static_cast<std::uint8_t>(order));
  scratch.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    scratch[i] = zigzag(static_cast<U>(values[i] - predicted(values.data(), i, order)));
  const std::size_t start = out.size();
  out.resize(start + n * sizeof(U));
  std::uint8_t* dst = out.data() + start;
  for (std::size_t b = 0; b < sizeof(U); ++b)
    for (std::size_t i = 0; i < n; ++i)
      *dst++ = static_cast<std::uint8_t>(scratch[i] >> (8 * b));
}

template <typename U>
bool get_column(Reader& rd, std::size_t n, std::vector<U>& values) {
  std::uint8_t order = 0;
  if (!rd.get(order) || (order != 1 && order != 2)) return false;
  if (rd.left() < n * sizeof(U)) return false;
  const std::uint8_t* src = rd.here();
  values.assign(n, 0);
  for (std::size_t b = 0; b < sizeof(U); ++b)
    for (std::size_t i = 0; i < n; ++i) values[i] |= static_cast<U>(*src++) << (8 * b);
  for (std::size_t i = 0; i < n; ++i)
    values[i] = static_cast<U>(unzigzag(values[i]) + predicted(values.data(), i, order));
  rd.skip(n * sizeof(U));
  return true;
}

// Starts a block: tag and a size placeholder; returns where the size goes.
std::size_t open_block(std::uint8_t tag, std::vector<std::uint8_t>& out) {
  out.push_back(tag);
  const std::size_t at = out.size();
  out.insert(out.end(), 4, 0);
  return at;
}
void close_block(std::size_t at, std::vector<std::uint8_t>& out) {
  const auto size = static_cast<std::uint32_t>(out.size() - at - 4);
  std::memcpy(out.data() + at, &size, 4);
}

bool decode_frame_block(Reader& rd, std::vector<Frame>& frames, const char** why) {
  std::uint32_t n = 0, zone_columns = 0;
  if (!rd.get(n) || !rd.get(zone_columns)) return *why = "truncated frame block", false;
  if (zone_columns > static_cast<std::uint32_t>(Frame::kZoneCapacity))
    return *why = "too many zone columns", false;
  // Each frame takes at least 8 bytes per double column: refuse counts the payload cannot hold.
  if (static_cast<std::uint64_t>(n) * 8 > rd.left()) return *why = "bad frame count", false;
  const std::size_t first = frames.size();
  frames.resize(first + n);
  Frame* block = frames.data() + first;
  std::vector<std::uint64_t> u64;
  for (F64Field field : kF64Fields) {
    if (!get_column(rd, n, u64)) return *why = "truncated frames", false;
    for (std::uint32_t i = 0; i < n; ++i) field(block[i]) = std::bit_cast<double>(u64[i]);
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!get_column(rd, n, u64)) return *why = "truncated frames", false;
    for (std::uint32_t i = 0; i < n; ++i)
      block[i].feedback_force_N[axis] = std::bit_cast<double>(
          u64[i] ^ std::bit_cast<std::uint64_t>(block[i].coupling_force_N[axis]));
  }
  std::vector<std::uint32_t> u32;
  for (I32Field field : kI32Fields) {
    if (!get_column(rd, n, u32)) return *why = "truncated frames", false;
    for (std::uint32_t i = 0; i < n; ++i) field(block[i]) = static_cast<std::int32_t>(u32[i]);
  }
  if (rd.left() < n) return *why = "truncated frames", false;
  for (std::uint32_t i = 0; i < n; ++i) block[i].input_valid = rd.here()[i] != 0;
  rd.skip(n);
  for (std::uint32_t k = 0; k < zone_columns; ++k) {
    if (!get_column(rd, n, u32)) return *why = "truncated zone samples", false;
    for (std::uint32_t i = 0; i < n; ++i)
      block[i].zones[k].distance_m = std::bit_cast<float>(u32[i]);
    if (!get_column(rd, n, u32)) return *why = "truncated zone samples", false;
    for (std::uint32_t i = 0; i < n; ++i) block[i].zones[k].force_N = std::bit_cast<float>(u32[i]);
    if (rd.left() < n) return *why = "truncated zone samples", false;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint8_t flags = rd.here()[i];
      block[i].zones[k].inside = (flags & 1) != 0;
      block[i].zones[k].warning = (flags & 2) != 0;
    }
    rd.skip(n);
  }
  return true;
}

bool decode_event(Reader& rd, Event& e, bool with_zone, const char** why) {
  std::uint8_t kind = 0;
  if (!(rd.get(e.t_s) && rd.get(kind) && rd.get(e.value))) return *why = "truncated events", false;
  if (with_zone && !rd.get(e.zone)) return *why = "truncated events", false;
  if (kind > static_cast<std::uint8_t>(kLastEventKind)) return *why = "unknown event", false;
  e.kind = static_cast<EventKind>(kind);
  if (!rd.get_text(e.detail)) return *why = "truncated event text", false;
  return true;
}

bool decode_event_block(Reader& rd, std::vector<Event>& events, const char** why) {
  std::uint32_t n = 0;
  if (!rd.get(n)) return *why = "truncated event block", false;
  if (static_cast<std::uint64_t>(n) * 25 > rd.left()) return *why = "bad event count", false;
  for (std::uint32_t i = 0; i < n; ++i) {
    Event e;
    if (!decode_event(rd, e, true, why)) return false;
    events.push_back(std::move(e));
  }
  return true;
}

void put_summary_v1(Writer& w, const WorldSummary& s) {
  w.put(s.dt_s), w.put(s.particle_volume_m3), w.put(s.initial_target), w.put(s.initial_protected);
  w.put(s.yield_moment_Nm), w.put(s.warning_moment_Nm), w.put(s.device_max_force_N);
}

bool get_summary_v1(Reader& rd, WorldSummary& s) {
  return rd.get(s.dt_s) && rd.get(s.particle_volume_m3) && rd.get(s.initial_target) &&
         rd.get(s.initial_protected) && rd.get(s.yield_moment_Nm) &&
         rd.get(s.warning_moment_Nm) && rd.get(s.device_max_force_N);
}

std::optional<AttemptRecording> decode_v1(Reader& rd, std::size_t size, const char** why) {
  AttemptRecording r;
  if (!get_summary_v1(rd, r.summary)) return *why = "truncated summary", std::nullopt;
  std::uint64_t n = 0;
  if (!rd.get(n) || n > kMaxCount) return *why = "bad frame count", std::nullopt;
  r.frames.resize(n);
  for (Frame& f : r.frames) {
    std::uint8_t valid = 0;
    if (!(rd.get(f.t_s) && rd.get_pose(f.device) && rd.get_pose(f.instrument) &&
          rd.get_vec(f.tip_m) && rd.get_vec(f.coupling_force_N) &&
          rd.get_vec(f.feedback_force_N) && rd.get_vec(f.nucleus_force_N) &&
          rd.get_vec(f.contact_force_N) && rd.get(f.bending_moment_Nm) &&
          rd.get(f.removed_target) && rd.get(f.removed_protected) && rd.get(f.broken_bonds) &&
          rd.get(f.active_particles) && rd.get(f.solver_iterations) && rd.get(valid)))
      return *why = "truncated frames", std::nullopt;
    f.input_valid = valid != 0;
  }
  if (!rd.get(n) || n > kMaxCount) return *why = "bad event count", std::nullopt;
  r.events.resize(n);
  for (Event& e : r.events)
    if (!decode_event(rd, e, false, why)) return std::nullopt;
  if (rd.pos != size) return *why = "trailing bytes", std::nullopt;
  return r;
}

bool decode_bone_block(Reader& rd, std::vector<BoneLoadRecord>& out, const char** why) {
  std::uint32_t n = 0;
  if (!rd.get(n)) return *why = "truncated bone load block", false;
  // Each sample takes at least 12 bytes: refuse counts the payload cannot hold.
  if (static_cast<std::uint64_t>(n) * 12 > rd.left()) return *why = "bad bone sample count", false;
  for (std::uint32_t k = 0; k < n; ++k) {
    BoneLoadRecord& r = out.emplace_back();
    std::uint32_t points = 0;
    if (!rd.get(r.t_s) || !rd.get(points)) return *why = "truncated bone loads", false;
    if (points > static_cast<std::uint32_t>(BoneLoadSample::kCapacity))
      return *why = "too many bone loads in a sample", false;
    r.points.resize(points);
    for (BoneLoadPoint& p : r.points) {
      std::uint8_t source = 0;
      if (!(rd.get(p.point_m.x()) && rd.get(p.point_m.y()) && rd.get(p.point_m.z()) &&
            rd.get(p.force_N.x()) && rd.get(p.force_N.y()) && rd.get(p.force_N.z()) &&
            rd.get(p.radius_m) && rd.get(p.vertebra) && rd.get(source)))
        return *why = "truncated bone loads", false;
      if (p.vertebra > 1 || source > static_cast<std::uint8_t>(BoneLoadSource::kNucleus))
        return *why = "bad bone load vertebra or source", false;
      p.source = static_cast<BoneLoadSource>(source);
    }
  }
  return true;
}

bool decode_removed_block(Reader& rd, std::optional<std::vector<Eigen::Vector3f>>& out,
                          const char** why) {
  std::uint32_t n = 0;
  if (!rd.get(n)) return *why = "truncated removed material block", false;
  if (static_cast<std::uint64_t>(n) * 12 > rd.left()) return *why = "bad removed particle count", false;
  if (out) return *why = "two removed material blocks", false;
  out.emplace(n);
  for (Eigen::Vector3f& p : *out)
    if (!(rd.get(p.x()) && rd.get(p.y()) && rd.get(p.z())))
      return *why = "truncated removed material", false;
  return true;
}

std::optional<AttemptRecording> decode_v2(Reader& rd, std::size_t size, const char** why) {
  AttemptRecording r;
  WorldSummary& s = r.summary;
  std::uint32_t zones = 0;
  if (!get_summary_v1(rd, s) || !rd.get(zones)) return *why = "truncated summary", std::nullopt;
  if (zones > static_cast<std::uint32_t>(Frame::kZoneCapacity))
    return *why = "too many zones", std::nullopt;
  s.zones.resize(zones);
  for (WorldSummary::Zone& z : s.zones) {
    std::uint8_t never = 0;
    if (!(rd.get_text(z.name) && rd.get(z.warning_distance_m) && rd.get(z.force_limit_N) &&
          rd.get(never)))
      return *why = "truncated zone list", std::nullopt;
    z.never_event = never != 0;
  }
  while (rd.pos < size) {
    std::uint8_t tag = 0;
    std::uint32_t payload = 0;
    if (!rd.get(tag) || !rd.get(payload) || payload > rd.left())
      return *why = "truncated block", std::nullopt;
    Reader block(rd.here(), payload);
    const bool ok = tag == kFramesTag      ? decode_frame_block(block, r.frames, why)
                    : tag == kEventsTag    ? decode_event_block(block, r.events, why)
                    : tag == kBoneLoadsTag ? decode_bone_block(block, r.bone_loads, why)
                    : tag == kRemovedTag   ? decode_removed_block(block, r.removed_positions, why)
                                           : (*why = "unknown block", false);
    if (!ok) return std::nullopt;
    if (block.pos != payload) return *why = "trailing bytes in a block", std::nullopt;
    rd.skip(payload);
  }
  return r;
}

}  // namespace

bool is_known_recording_format(std::string_view format) {
  return format == kRecordingFormat || format == kRecordingFormatV1;
}

std::vector<std::uint8_t> encode_recording_header(const WorldSummary& s) {
  // reserve first: GCC 12 warns falsely (-Warray-bounds) on growing an 8-byte vector.
  std::vector<std::uint8_t> out;
  out.reserve(256);
  out.insert(out.end(), kMagicV2, kMagicV2 + 8);
  Writer w(out);
  w.put(std::uint32_t{2});
  put_summary_v1(w, s);
  w.put(static_cast<std::uint32_t>(s.zones.size()));
  for (const WorldSummary::Zone& z : s.zones) {
    w.put_text(z.name);
    w.put(z.warning_distance_m), w.put(z.force_limit_N);
    w.put(static_cast<std::uint8_t>(z.never_event));
  }
  return out;
}

void append_frame_block(std::span<const Frame> frames, std::vector<std::uint8_t>& out) {
  if (frames.empty()) return;
  const std::size_t n = frames.size();
  std::int32_t zone_columns = 0;
  for (const Frame& f : frames)
    zone_columns = std::max(zone_columns, std::clamp(f.zone_count, 0, Frame::kZoneCapacity));
  const std::size_t at = open_block(kFramesTag, out);
  Writer w(out);
  w.put(static_cast<std::uint32_t>(n));
  w.put(static_cast<std::uint32_t>(zone_columns));
  // The getters need a mutable frame; nothing is written through them here.
  auto& rows = const_cast<Frame&>(frames.front());
  Frame* row = &rows;
  std::vector<std::uint64_t> u64(n), s64;
  for (F64Field field : kF64Fields) {
    for (std::size_t i = 0; i < n; ++i) u64[i] = std::bit_cast<std::uint64_t>(field(row[i]));
    put_column(u64, s64, out);
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t i = 0; i < n; ++i)
      u64[i] = std::bit_cast<std::uint64_t>(row[i].feedback_force_N[axis]) ^
               std::bit_cast<std::uint64_t>(row[i].coupling_force_N[axis]);
    put_column(u64, s64, out);
  }
  std::vector<std::uint32_t> u32(n), s32;
  for (I32Field field : kI32Fields) {
    for (std::size_t i = 0; i < n; ++i) u32[i] = static_cast<std::uint32_t>(field(row[i]));
    put_column(u32, s32, out);
  }
  for (const Frame& f : frames) out.push_back(static_cast<std::uint8_t>(f.input_valid));
  for (std::int32_t k = 0; k < zone_columns; ++k) {
    for (std::size_t i = 0; i < n; ++i) u32[i] = std::bit_cast<std::uint32_t>(row[i].zones[k].distance_m);
    put_column(u32, s32, out);
    for (std::size_t i = 0; i < n; ++i) u32[i] = std::bit_cast<std::uint32_t>(row[i].zones[k].force_N);
    put_column(u32, s32, out);
    for (std::size_t i = 0; i < n; ++i)
      out.push_back(static_cast<std::uint8_t>((row[i].zones[k].inside ? 1 : 0) |
                                              (row[i].zones[k].warning ? 2 : 0)));
  }
  close_block(at, out);
}

void append_event_block(std::span<const Event> events, std::vector<std::uint8_t>& out) {
  if (events.empty()) return;
  const std::size_t at = open_block(kEventsTag, out);
  Writer w(out);
  w.put(static_cast<std::uint32_t>(events.size()));
  for (const Event& e : events) {
    w.put(e.t_s);
    w.put(static_cast<std::uint8_t>(e.kind));
    w.put(e.value);
    w.put(e.zone);
    w.put_text(e.detail);
  }
  close_block(at, out);
}

void append_bone_load_block(std::span<const BoneLoadRecord> samples,
                            std::vector<std::uint8_t>& out) {
  if (samples.empty()) return;
  const std::size_t at = open_block(kBoneLoadsTag, out);
  Writer w(out);
  w.put(static_cast<std::uint32_t>(samples.size()));
  for (const BoneLoadRecord& r : samples) {
    w.put(r.t_s);
    w.put(static_cast<std::uint32_t>(r.points.size()));
    for (const BoneLoadPoint& p : r.points) {
      for (int a = 0; a < 3; ++a) w.put(p.point_m[a]);
      for (int a = 0; a < 3; ++a) w.put(p.force_N[a]);
      w.put(p.radius_m);
      w.put(p.vertebra);
      w.put(static_cast<std::uint8_t>(p.source));
    }
  }
  close_block(at, out);
}

void append_removed_block(std::span<const Eigen::Vector3f> positions,
                          std::vector<std::uint8_t>& out) {
  const std::size_t at = open_block(kRemovedTag, out);
  Writer w(out);
  w.put(static_cast<std::uint32_t>(positions.size()));
  for (const Eigen::Vector3f& p : positions) w.put(p.x()), w.put(p.y()), w.put(p.z());
  close_block(at, out);
}

std::vector<std::uint8_t> encode_recording(const AttemptRecording& r) {
  std::vector<std::uint8_t> out = encode_recording_header(r.summary);
  const std::span<const Frame> frames(r.frames);
  for (std::size_t i = 0; i < frames.size(); i += kRecordingBlockFrames)
    append_frame_block(frames.subspan(i, std::min(kRecordingBlockFrames, frames.size() - i)), out);
  append_event_block(r.events, out);
  append_bone_load_block(r.bone_loads, out);
  if (r.removed_positions) append_removed_block(*r.removed_positions, out);
  return out;
}

std::vector<std::uint8_t> encode_recording_v1(const AttemptRecording& r) {
  // reserve first: GCC 12 warns falsely (-Warray-bounds) on growing an 8-byte vector.
  std::vector<std::uint8_t> out;
  out.reserve(256);
  out.insert(out.end(), kMagicV1, kMagicV1 + 8);
  Writer w(out);
  w.put(std::uint32_t{1});
  put_summary_v1(w, r.summary);
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
    w.put_text(e.detail);
  }
  return out;
}

std::optional<AttemptRecording> decode_recording(const std::vector<std::uint8_t>& bytes,
                                                 std::string* error) {
  const char* why = nullptr;
  auto fail = [&](const char* reason) {
    if (error) *error = std::string("recording: ") + reason;
    return std::nullopt;
  };
  if (bytes.size() < 8) return fail("not an ACDR recording");
  const bool v1 = std::memcmp(bytes.data(), kMagicV1, 8) == 0;
  const bool v2 = std::memcmp(bytes.data(), kMagicV2, 8) == 0;
  if (!v1 && !v2) return fail("not an ACDR recording");
  Reader rd(bytes.data(), bytes.size());
  rd.pos = 8;
  std::uint32_t version = 0;
  if (!rd.get(version) || version != (v1 ? 1u : 2u)) return fail("unknown recording version");
  std::optional<AttemptRecording> r = v1 ? decode_v1(rd, bytes.size(), &why)
                                         : decode_v2(rd, bytes.size(), &why);
  if (!r) return fail(why ? why : "damaged");
  return r;
}

}  // namespace acdr

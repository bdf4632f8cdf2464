// The side file of an attempt whose record could not be written: see outcome_side_file.hpp.
#include "db/outcome_side_file.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>
#include <utility>

#include "db/attempt_store.hpp"
#include "db/database.hpp"
#include "db/recording_codec.hpp"
#include "db/utc_time.hpp"

namespace acdr {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kMagic = "acdr-unsaved-attempt\n";
// 2: the real-time factor after the duration. Version 1 files (without it) are still read.
constexpr std::uint32_t kFormatVersion = 2;
constexpr std::string_view kSuffix = ".unsaved";
// Far above any attempt's recording (a 20-minute attempt compresses to ~110 MB) and below
// what would exhaust memory when read back.
constexpr std::uintmax_t kMaxSideFileBytes = std::uintmax_t{2} << 30;

class Writer {
 public:
  void u8(std::uint8_t v) { bytes_.push_back(v); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  void str(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }
  void raw(const std::uint8_t* p, std::size_t n) { bytes_.insert(bytes_.end(), p, p + n); }
  std::vector<std::uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

// Reads with bounds checks; the first failure is kept (with its byte offset) and every later
// read returns zero, so the caller checks once at the end.
class Reader {
 public:
  Reader(const std::vector<std::uint8_t>& bytes, std::size_t end) : bytes_(bytes), end_(end) {}

  bool take(std::size_t n, const char* what) {
    if (!error_.empty()) return false;
    if (n > end_ - pos_) {
      error_ = "at byte " + std::to_string(pos_) + ": " + what + " needs " + std::to_string(n) +
               " bytes, only " + std::to_string(end_ - pos_) + " left (truncated?)";
      return false;
    }
    return true;
  }
  // The next `n` bytes (advancing past them), or null when fewer are left.
  const std::uint8_t* span_of(std::uint64_t n, const char* what) {
    if (n > end_ - pos_) {
      take(end_ - pos_ + 1, what);
      return nullptr;
    }
    if (!take(static_cast<std::size_t>(n), what)) return nullptr;
    const std::uint8_t* p = bytes_.data() + pos_;
    pos_ += static_cast<std::size_t>(n);
    return p;
  }
  std::uint64_t uint(int size, const char* what) {
    if (!take(static_cast<std::size_t>(size), what)) return 0;
    std::uint64_t v = 0;
    for (int i = 0; i < size; ++i) v |= static_cast<std::uint64_t>(bytes_[pos_++]) << (8 * i);
    return v;
  }
  std::uint8_t u8(const char* what) { return static_cast<std::uint8_t>(uint(1, what)); }
  std::uint32_t u32(const char* what) { return static_cast<std::uint32_t>(uint(4, what)); }
  std::uint64_t u64(const char* what) { return uint(8, what); }
  std::int64_t i64(const char* what) { return static_cast<std::int64_t>(u64(what)); }
  double f64(const char* what) {
    const std::uint64_t bits = u64(what);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  bool flag(const char* what) {
    const std::uint8_t v = u8(what);
    if (v > 1) fail(std::string(what) + " is " + std::to_string(v) + " (expected 0 or 1)");
    return v == 1;
  }
  std::string str(const char* what) {
    const std::uint32_t n = u32(what);
    if (!take(n, what)) return {};
    std::string s(reinterpret_cast<const char*>(bytes_.data() + pos_), n);
    pos_ += n;
    return s;
  }
  // A count of items that each take at least `min_item_bytes`: more than could fit is damage.
  std::uint32_t count(const char* what, std::size_t min_item_bytes) {
    const std::uint32_t n = u32(what);
    if (error_.empty() && static_cast<std::uint64_t>(n) * min_item_bytes > end_ - pos_) {
      fail(std::string(what) + ": " + std::to_string(n) + " items cannot fit in the " +
           std::to_string(end_ - pos_) + " bytes left");
      return 0;
    }
    return error_.empty() ? n : 0;
  }
  void fail(const std::string& what) {
    if (error_.empty()) error_ = "at byte " + std::to_string(pos_) + ": " + what;
  }
  std::size_t pos() const { return pos_; }
  const std::string& error() const { return error_; }

 private:
  const std::vector<std::uint8_t>& bytes_;
  std::size_t end_;
  std::size_t pos_ = 0;
  std::string error_;
};

std::uint32_t crc_of(const std::uint8_t* p, std::size_t n) {
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes the length as uInt: feed large buffers in pieces.
  while (n > 0) {
    const uInt piece = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    crc = crc32(crc, p, piece);
    p += piece;
    n -= piece;
  }
  return static_cast<std::uint32_t>(crc);
}

std::string system_error_text(const std::string& path, const char* what) {
  return path + ": " + what + ": " + std::strerror(errno);
}

// Writes all of `bytes` to `fd`.
bool write_all(int fd, const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

fs::path directory_of(const std::string& db_path) {
  fs::path dir = fs::path(db_path).parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

// The attempt id in a side file's name, or -1 when `name` is not one of `db_path`'s.
std::int64_t id_in_name(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() + kSuffix.size() ||
      name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - kSuffix.size(), kSuffix.size(), kSuffix) != 0)
    return -1;
  const std::string digits =
      name.substr(prefix.size(), name.size() - prefix.size() - kSuffix.size());
  if (digits.empty() || digits.size() > 18 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return -1;
  return std::stoll(digits);
}

std::string name_prefix(const std::string& db_path) {
  return fs::path(db_path).filename().string() + ".attempt-";
}

// The attempt's uuid and status in the record (nullopt: no such attempt).
struct AttemptIdentity {
  std::string uuid;
  std::string status;
};
DbResult<std::optional<AttemptIdentity>> attempt_identity(Database& db, std::int64_t id) {
  DbResult<Statement> s = db.prepare("SELECT uuid, status FROM attempts WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(id); !b) return b.error();
  DbResult<bool> row = s->step();
  if (!row) return row.error();
  if (!row.value()) return std::optional<AttemptIdentity>();
  return std::optional<AttemptIdentity>(AttemptIdentity{s->column_text(0), s->column_text(1)});
}

std::string attempt_label(std::int64_t id) {
  return "attempt " + std::to_string(id);
}

// Writes `bytes` to `path` atomically: the whole file under a temporary name, synced, then
// renamed over the final name and the directory synced, so the file is either absent or
// complete.
DbStatus write_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  const std::string temp = path + ".tmp-" + std::to_string(::getpid());
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) return DbError{system_error_text(temp, "cannot create the side file"), 0};
  const bool written = write_all(fd, bytes);
  const int write_errno = errno;
  const bool synced = written && ::fsync(fd) == 0;
  const int sync_errno = errno;
  ::close(fd);
  if (!written || !synced) {
    errno = written ? sync_errno : write_errno;
    DbError err{system_error_text(
                    temp, written ? "cannot sync the side file" : "cannot write the side file"),
                0};
    ::unlink(temp.c_str());
    return err;
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    DbError err{system_error_text(path, "cannot rename the side file into place"), 0};
    ::unlink(temp.c_str());
    return err;
  }
  const fs::path parent = fs::path(path).parent_path();
  const int dir =
      ::open(parent.empty() ? "." : parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    (void)::fsync(dir);  // best effort: the file itself is already synced
    ::close(dir);
  }
  return {};
}

// In the fallback directory, side files of many records meet: their names start with the
// CRC-32 of the record's absolute path, then the attempt.
std::string fallback_prefix(const std::string& db_path) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(db_path, ec);
  const std::string key = (ec ? fs::path(db_path) : absolute).lexically_normal().string();
  char hex[16];
  std::snprintf(hex, sizeof hex, "%08x",
                crc_of(reinterpret_cast<const std::uint8_t*>(key.data()), key.size()));
  return std::string(hex) + ".attempt-";
}

// The side files in `dir` whose names start with `prefix`, with their attempt ids.
void collect(const fs::path& dir, const std::string& prefix,
             std::vector<std::pair<std::int64_t, std::string>>& found) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::int64_t id = id_in_name(it->path().filename().string(), prefix);
    if (id > 0) found.emplace_back(id, it->path().string());
  }
}

}  // namespace

std::string unsaved_outcome_path(const std::string& db_path, std::int64_t attempt_id) {
  // In the database's directory, written as the database's path was (relative stays relative).
  return (fs::path(db_path).parent_path() /
          (name_prefix(db_path) + std::to_string(attempt_id) + std::string(kSuffix)))
      .string();
}

DbResult<std::string> write_unsaved_outcome(const std::string& db_path,
                                            const UnsavedOutcome& unsaved) {
  const AttemptOutcome& o = unsaved.outcome;
  Writer w;
  w.raw(reinterpret_cast<const std::uint8_t*>(kMagic.data()), kMagic.size());
  w.u32(kFormatVersion);
  w.i64(unsaved.attempt_id);
  w.str(unsaved.attempt_uuid);
  w.str(o.ended_utc);
  w.f64(o.duration_s);
  w.f64(o.realtime_factor);
  w.u32(static_cast<std::uint32_t>(o.metrics.values.size()));
  for (const auto& [name, value] : o.metrics.values) {
    w.str(name);
    w.f64(value);
  }
  w.f64(o.score.score);
  w.u8(o.score.passed ? 1 : 0);
  w.u32(static_cast<std::uint32_t>(o.score.terms.size()));
  for (const TermScore& t : o.score.terms) {
    w.str(t.metric);
    w.f64(t.value);
    w.f64(t.score);
  }
  w.u32(static_cast<std::uint32_t>(o.score.gates.size()));
  for (const GateResult& g : o.score.gates) {
    w.str(g.metric);
    w.f64(g.value);
    w.f64(g.max);
    w.u8(g.passed ? 1 : 0);
  }
  w.u32(static_cast<std::uint32_t>(o.score.reasons.size()));
  for (const std::string& r : o.score.reasons) w.str(r);
  w.u32(static_cast<std::uint32_t>(o.events.size()));
  for (const EventRecord& e : o.events) {
    w.f64(e.t_s);
    w.str(e.kind);
    w.str(e.zone);
    w.f64(e.value);
    w.str(e.detail);
    w.u32(static_cast<std::uint32_t>(e.zone_index));
  }
  w.u8(o.recording ? 1 : 0);
  if (o.recording) {
    DbResult<std::vector<std::uint8_t>> packed = compress_recording(o.recording->bytes);
    if (!packed) return packed.error();
    w.str(o.recording->format);
    w.i64(o.recording->frame_count);
    w.u64(o.recording->bytes.size());
    w.u64(packed->size());
    w.raw(packed->data(), packed->size());
  }
  w.u32(crc_of(w.bytes().data(), w.bytes().size()));

  // Next to the database; if that fails (the disk that is full is usually the database's),
  // in the fallback directory, which the next start searches too.
  const std::string path = unsaved_outcome_path(db_path, unsaved.attempt_id);
  DbStatus here = write_atomically(path, w.bytes());
  if (here) return path;
  const fs::path elsewhere = unsaved_fallback_directory();
  std::error_code ec;
  fs::create_directories(elsewhere, ec);
  const std::string fallback =
      (elsewhere / (fallback_prefix(db_path) + std::to_string(unsaved.attempt_id) +
                    std::string(kSuffix)))
          .string();
  DbStatus there = ec ? DbStatus(DbError{elsewhere.string() + ": " + ec.message(), 0})
                      : write_atomically(fallback, w.bytes());
  if (there) return fallback;
  return DbError{here.error().message + "; nor in " + there.error().message, 0};
}

DbResult<UnsavedOutcome> read_unsaved_outcome(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::is_regular_file(status))
    return DbError{path + ": not a regular file (expected a side file of an unsaved attempt)", 0};
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size > kMaxSideFileBytes)
    return DbError{path + ": " + (ec ? ec.message() : std::to_string(size) + " bytes") +
                       " (expected a side file of at most " + std::to_string(kMaxSideFileBytes) +
                       " bytes)",
                   0};
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
    return DbError{path + ": cannot read the side file", 0};
  auto damaged = [&](const std::string& what) {
    return DbError{path + ": not a readable side file: " + what, 0};
  };
  if (size < kMagic.size() + 4 || std::memcmp(bytes.data(), kMagic.data(), kMagic.size()) != 0)
    return damaged("it does not start with \"acdr-unsaved-attempt\"");
  const std::size_t body = bytes.size() - 4;
  std::uint32_t stored_crc = 0;
  for (int i = 0; i < 4; ++i) stored_crc |= static_cast<std::uint32_t>(bytes[body + i]) << (8 * i);
  if (crc_of(bytes.data(), body) != stored_crc)
    return damaged("its CRC-32 does not match (damaged)");

  Reader r(bytes, body);
  r.span_of(kMagic.size(), "magic");
  const std::uint32_t version = r.u32("version");
  if (r.error().empty() && (version < 1 || version > kFormatVersion))
    return damaged("format version " + std::to_string(version) + " (expected 1 to " +
                   std::to_string(kFormatVersion) + ")");
  UnsavedOutcome u;
  AttemptOutcome& o = u.outcome;
  u.attempt_id = r.i64("attempt id");
  u.attempt_uuid = r.str("attempt uuid");
  o.ended_utc = r.str("end time");
  o.duration_s = r.f64("duration");
  if (version >= 2) o.realtime_factor = r.f64("real-time factor");
  for (std::uint32_t i = 0, n = r.count("metrics", 12); i < n; ++i) {
    std::string name = r.str("metric name");
    o.metrics.values.emplace_back(std::move(name), r.f64("metric value"));
  }
  o.score.score = r.f64("score");
  o.score.passed = r.flag("passed");
  for (std::uint32_t i = 0, n = r.count("score terms", 20); i < n; ++i) {
    TermScore t;
    t.metric = r.str("term metric");
    t.value = r.f64("term value");
    t.score = r.f64("term score");
    o.score.terms.push_back(std::move(t));
  }
  for (std::uint32_t i = 0, n = r.count("gates", 21); i < n; ++i) {
    GateResult g;
    g.metric = r.str("gate metric");
    g.value = r.f64("gate value");
    g.max = r.f64("gate max");
    g.passed = r.flag("gate passed");
    o.score.gates.push_back(std::move(g));
  }
  for (std::uint32_t i = 0, n = r.count("reasons", 4); i < n; ++i)
    o.score.reasons.push_back(r.str("reason"));
  for (std::uint32_t i = 0, n = r.count("events", 32); i < n; ++i) {
    EventRecord e;
    e.t_s = r.f64("event time");
    e.kind = r.str("event kind");
    e.zone = r.str("event zone");
    e.value = r.f64("event value");
    e.detail = r.str("event detail");
    e.zone_index = static_cast<std::int32_t>(r.u32("event zone index"));
    o.events.push_back(std::move(e));
  }
  if (r.flag("has recording")) {
    RecordingData rec;
    rec.format = r.str("recording format");
    rec.frame_count = r.i64("recording frame count");
    const std::uint64_t raw_size = r.u64("recording raw size");
    const std::uint64_t packed_size = r.u64("recording size");
    if (const std::uint8_t* packed = r.span_of(packed_size, "recording")) {
      DbResult<std::vector<std::uint8_t>> raw = decompress_recording(
          std::span<const std::uint8_t>(packed, static_cast<std::size_t>(packed_size)), raw_size);
      if (!raw) return damaged("its recording does not inflate: " + raw.error().message);
      rec.bytes = std::move(raw.value());
    }
    o.recording = std::move(rec);
  }
  if (!r.error().empty()) return damaged(r.error());
  if (r.pos() != body)
    return damaged(std::to_string(body - r.pos()) + " bytes left over after the last field");
  if (u.attempt_id <= 0) return damaged("attempt id " + std::to_string(u.attempt_id));
  if (!parse_utc(o.ended_utc)) return damaged("end time '" + o.ended_utc + "' is not UTC");
  return u;
}

std::string unsaved_fallback_directory() {
  // XDG Base Directory: state data lives in $XDG_STATE_HOME (absolute), else ~/.local/state.
  if (const char* xdg = std::getenv("XDG_STATE_HOME"); xdg && xdg[0] == '/')
    return (fs::path(xdg) / "acdr" / "unsaved").string();
  if (const char* home = std::getenv("HOME"); home && *home)
    return (fs::path(home) / ".local" / "state" / "acdr" / "unsaved").string();
  return (fs::temp_directory_path() / "acdr-unsaved").string();
}

std::vector<std::string> find_unsaved_outcomes(const std::string& db_path) {
  std::vector<std::pair<std::int64_t, std::string>> found;
  collect(directory_of(db_path), name_prefix(db_path), found);
  collect(unsaved_fallback_directory(), fallback_prefix(db_path), found);
  std::sort(found.begin(), found.end());
  std::vector<std::string> paths;
  for (auto& f : found) paths.push_back(std::move(f.second));
  return paths;
}

UnsavedReplay store_unsaved_outcomes(Database& db) {
  UnsavedReplay replay;
  if (db.path() == ":memory:") return replay;
  for (const std::string& path : find_unsaved_outcomes(db.path())) {
    DbResult<UnsavedOutcome> unsaved = read_unsaved_outcome(path);
    if (!unsaved) {
      replay.notes.push_back(unsaved.error().message + "; left in place");
      continue;
    }
    const std::int64_t id = unsaved->attempt_id;
    const std::string label = attempt_label(id);
    DbResult<std::optional<AttemptIdentity>> row = attempt_identity(db, id);
    if (!row) {
      replay.notes.push_back(path + ": " + label + " not stored yet (" + row.error().message +
                             "); the side file stays");
      replay.still_pending.push_back(id);
      continue;
    }
    if (!row.value() ||
        (!unsaved->attempt_uuid.empty() && row.value()->uuid != unsaved->attempt_uuid)) {
      replay.notes.push_back(path + ": " + label + " " + unsaved->attempt_uuid + " is not in " +
                             db.path() +
                             " (another record's side file?); "
                             "left in place");
      continue;
    }
    if (row.value()->status == "running") {
      DbStatus stored = finish_attempt(db, id, unsaved->outcome);
      if (!stored) {
        // Another program may have stored it in between; otherwise it waits for the next start.
        DbResult<std::optional<AttemptIdentity>> again = attempt_identity(db, id);
        if (!again || !again.value() || again.value()->status != "completed") {
          replay.notes.push_back(label + ": its result, kept in " + path +
                                 ", still cannot be stored (" + stored.error().message +
                                 "); it stays there for the next start");
          replay.still_pending.push_back(id);
          continue;
        }
      } else {
        replay.notes.push_back(label + ": its result, kept in " + path +
                               " because the record could not be written when it ended, is "
                               "now stored in " +
                               db.path() + " (completed)");
      }
    } else if (row.value()->status == "aborted") {
      replay.notes.push_back(label + " is already aborted in " + db.path() +
                             "; its result stays in " + path);
      continue;
    }
    std::error_code ec;
    fs::remove(path, ec);  // completed in the record: the side file has served
  }
  return replay;
}

FinalRecord finish_attempt_or_keep(Database& db, std::int64_t attempt_id, AttemptOutcome outcome,
                                   double patience_s, const XapiOptions& xapi) {
  FinalRecord result;
  // The end is now, whenever the record is finally written; the uuid (a read, which another
  // connection's write lock does not block in WAL mode) ties the side file to this attempt.
  if (outcome.ended_utc.empty()) outcome.ended_utc = utc_now_text();
  std::string uuid;
  if (auto row = attempt_identity(db, attempt_id); row && row.value()) uuid = row.value()->uuid;
  const DbStatus stored = finish_attempt_patiently(db, attempt_id, outcome, patience_s, xapi);
  if (stored) {
    result.stored = true;
    return result;
  }
  result.error = stored.error().message;
  DbResult<std::string> kept =
      write_unsaved_outcome(db.path(), UnsavedOutcome{attempt_id, uuid, std::move(outcome)});
  if (kept) {
    result.side_file = kept.value();
  } else {
    result.error += "; and the side file could not be written either: " + kept.error().message;
  }
  return result;
}

}  // namespace acdr

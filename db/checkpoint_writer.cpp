// Checkpoints from an attempt's record: see checkpoint_writer.hpp.
#include "db/checkpoint_writer.hpp"

#include <ostream>

#include "assessment/metrics.hpp"
#include "assessment/recording.hpp"
#include "db/attempt_store.hpp"

namespace acdr {

std::vector<EventRecord> event_records(std::span<const Event> events,
                                       const std::vector<WorldSummary::Zone>& zones) {
  std::vector<EventRecord> out;
  out.reserve(events.size());
  for (const Event& e : events) {
    const bool known = e.zone >= 0 && static_cast<std::size_t>(e.zone) < zones.size();
    out.push_back(EventRecord{e.t_s, event_kind_name(e.kind),
                              known ? zones[static_cast<std::size_t>(e.zone)].name : std::string(),
                              e.value, e.detail, known ? e.zone : -1});
  }
  return out;
}

CheckpointWriter::CheckpointWriter(Database& db, std::int64_t attempt_id, std::ostream& err)
    : db_(db), attempt_id_(attempt_id), err_(err) {}

bool CheckpointWriter::write(const AttemptRecording& record, std::size_t first_new_frame,
                             std::size_t first_new_event, std::size_t first_new_bone_sample,
                             double t_s) {
  AttemptCheckpoint checkpoint;
  RecordingData chunk;
  chunk.format = kRecordingFormat;
  chunk.complete = false;
  // The v2 stream is a header and then blocks, so the pieces concatenate into one recording.
  if (!header_saved_) chunk.bytes = encode_recording_header(record.summary);
  const std::span<const Frame> frames =
      std::span<const Frame>(record.frames).subspan(first_new_frame);
  const std::span<const Event> events =
      std::span<const Event>(record.events).subspan(first_new_event);
  append_frame_block(frames, chunk.bytes);
  append_event_block(events, chunk.bytes);
  append_bone_load_block(std::span<const BoneLoadRecord>(record.bone_loads).subspan(first_new_bone_sample),
                         chunk.bytes);
  chunk.frame_count = static_cast<std::int64_t>(frames.size());
  checkpoint.chunk = std::move(chunk);
  checkpoint.new_events = event_records(events, record.summary.zones);
  checkpoint.metrics = compute_metrics(record);
  checkpoint.duration_s = t_s;
  if (auto saved = append_checkpoint(db_, attempt_id_, checkpoint); !saved) {
    if (!warned_) err_ << "warning: checkpoint not saved: " << saved.error().message << "\n";
    warned_ = true;
    return false;
  }
  header_saved_ = true;
  ++saved_;
  return true;
}

}  // namespace acdr

// The recording of an attempt: its AttemptRecording as a compact, versioned byte string
// (format "acdr-frames-v1"), stored with the attempt (the store compresses it) so that it can be
// replayed and re-scored.
//
// Layout (little-endian, IEEE-754 doubles): "ACDRREC1", u32 version,
// the WorldSummary, u64 frame count, the frames field by field, u64 event count, the events.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "assessment/attempt_recording.hpp"

namespace acdr {

/// Name of this layout, stored beside the bytes.
inline constexpr const char* kRecordingFormat = "acdr-frames-v1";

std::vector<std::uint8_t> encode_recording(const AttemptRecording& record);

/// Decodes a recording; on damaged or foreign data returns nullopt with the reason.
std::optional<AttemptRecording> decode_recording(const std::vector<std::uint8_t>& bytes,
                                              std::string* error);

}  // namespace acdr

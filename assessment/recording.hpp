// The recording of an attempt: its AttemptRecord as a compact, versioned, zlib-compressed byte
// string, stored with the attempt so that it can be replayed and re-scored.
//
// Layout before compression (little-endian, IEEE-754 doubles): "ACDRREC1", u32 version,
// the WorldSummary, u64 frame count, the frames field by field, u64 event count, the events.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "assessment/attempt_record.hpp"

namespace acdr {

std::vector<std::uint8_t> encode_recording(const AttemptRecord& record);

/// Decodes a recording; on damaged or foreign data returns nullopt with the reason.
std::optional<AttemptRecord> decode_recording(const std::vector<std::uint8_t>& bytes,
                                              std::string* error);

}  // namespace acdr

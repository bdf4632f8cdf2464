// The recording of an attempt: its AttemptRecording as a compact, versioned byte string, stored
// with the attempt (the store compresses it with zlib) so that it can be replayed and re-scored
// without the scenario's live engine.
//
// Format "acdr-frames-v2" (current; little-endian, IEEE-754):
//   header  "ACDRREC2", u32 version 2, the WorldSummary including its danger zones (name,
//           warning distance, force limit, never-event flag: what zone metrics need);
//   blocks  until the end of the bytes, each u8 tag, u32 payload size, payload:
//           'F' frames: u32 count, u32 zone columns, then every field as one column (structure
//               of arrays). A column of doubles/floats/ints is a u8 predictor order (1: the
//               previous value, 2: linear extrapolation from the two previous; the encoder
//               picks the one with smaller residuals) and the zigzag-coded residuals of the
//               values' bit patterns, byte-shuffled (all lowest bytes, then all next bytes,
//               ...). Smooth 1 kHz signals then differ only in their low mantissa bytes and
//               zlib finds long runs in the high ones. The feedback force is stored as the XOR
//               of its bits with the coupling force's (it is mostly exactly its negative).
//               Lossless: decoding gives the same bits, so metrics re-compute exactly.
//           'E' events: u32 count, per event f64 t, u8 kind, f64 value, i32 zone, u32 length +
//               the detail text.
//           'B' bone loads (only when the scene models the bone, engine/core/bone_load.hpp):
//               u32 count, per sample f64 t, u32 loads, per load f32 point x y z (m),
//               f32 force x y z (N), f32 patch radius (m), u8 vertebra (0 C4, 1 C5), u8
//               source (0 instrument, 1 nucleus). Single precision is what the live solves
//               used, so the bone metrics re-compute exactly.
//           'R' removed material (once, at the end of an attempt): u32 count, per removed
//               particle f32 x y z (m), in particle order; what the lump metrics read.
//   The header and blocks concatenate: a recording can be written piece by piece (periodic
//   checkpoints of a running attempt) and any prefix that ends on a block boundary decodes.
// Format "acdr-frames-v1" (magic "ACDRREC1", row by row, no zones) is still read.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "assessment/attempt_recording.hpp"

namespace acdr {

/// Name of the layout encode_recording writes, stored beside the bytes.
inline constexpr const char* kRecordingFormat = "acdr-frames-v2";
/// The first layout (row by row, no zone data), still decoded.
inline constexpr const char* kRecordingFormatV1 = "acdr-frames-v1";

/// Whether decode_recording reads recordings stored under this format name.
bool is_known_recording_format(std::string_view format);

/// The whole recording: header, frames in blocks of up to kRecordingBlockFrames, one block of
/// all events, one block of all bone load samples (when there are any), the removed material
/// (when the record has it).
std::vector<std::uint8_t> encode_recording(const AttemptRecording& record);

/// Frames per 'F' block written by encode_recording (about 4 s at 1 kHz).
inline constexpr std::size_t kRecordingBlockFrames = 4096;

/// Piecewise writing (checkpoints): the header first, then any sequence of frame and event
/// blocks appended to `out`; the concatenation decodes like encode_recording's output.
std::vector<std::uint8_t> encode_recording_header(const WorldSummary& summary);
/// Appends one 'F' block with `frames` (nothing when empty).
void append_frame_block(std::span<const Frame> frames, std::vector<std::uint8_t>& out);
/// Appends one 'E' block with `events` (nothing when empty).
void append_event_block(std::span<const Event> events, std::vector<std::uint8_t>& out);
/// Appends one 'B' block with `samples` (nothing when empty).
void append_bone_load_block(std::span<const BoneLoadRecord> samples,
                            std::vector<std::uint8_t>& out);

/// Appends the 'R' block: where the removed particles lie at the end (written even when empty,
/// so "nothing removed" differs from "not recorded").
void append_removed_block(std::span<const Eigen::Vector3f> positions,
                          std::vector<std::uint8_t>& out);

/// The v1 layout, kept so reading old recordings stays tested and sizes can be compared.
std::vector<std::uint8_t> encode_recording_v1(const AttemptRecording& record);

/// Decodes a v2 or v1 recording; on damaged or foreign data returns nullopt with the reason.
std::optional<AttemptRecording> decode_recording(const std::vector<std::uint8_t>& bytes,
                                                 std::string* error);

}  // namespace acdr

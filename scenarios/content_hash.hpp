// FNV-1a 64-bit hash of a byte string: the scenario's identity stored with every attempt, so a
// result can always be traced to the exact file that produced it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace acdr {

/// FNV-1a, 64 bits (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
std::uint64_t fnv1a64(std::string_view bytes);

/// The hash as 16 lower-case hex digits.
std::string fnv1a64_hex(std::string_view bytes);

}  // namespace acdr

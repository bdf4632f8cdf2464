// FNV-1a 64-bit hashing of raw bytes, for determinism checks and scenario fingerprints.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace acdr {

inline constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
inline constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

/// Continues an FNV-1a 64 hash over `size` bytes.
inline std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t hash = kFnvOffset) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= kFnvPrime;
  }
  return hash;
}

inline std::uint64_t fnv1a(std::string_view text, std::uint64_t hash = kFnvOffset) {
  return fnv1a(text.data(), text.size(), hash);
}

/// 16 lowercase hex digits.
std::string hash_hex(std::uint64_t hash);

}  // namespace acdr

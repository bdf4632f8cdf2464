// FNV-1a 64 (Fowler, Noll, Vo): xor each byte in, then multiply by the FNV prime.
#include "scenarios/content_hash.hpp"

namespace acdr {

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string fnv1a64_hex(std::string_view bytes) {
  static const char* kDigits = "0123456789abcdef";
  std::uint64_t h = fnv1a64(bytes);
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i) {
    out[static_cast<std::size_t>(i)] = kDigits[h & 0xfu];
    h >>= 4;
  }
  return out;
}

}  // namespace acdr

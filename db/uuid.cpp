// UUIDs v4 and v5 and the SHA-1 that v5 needs: see uuid.hpp.
#include "db/uuid.hpp"

#include <array>
#include <cstdint>
#include <random>

#include <sys/random.h>
#include <sys/types.h>

namespace acdr {

namespace {

using Bytes16 = std::array<std::uint8_t, 16>;
using Digest20 = std::array<std::uint8_t, 20>;

std::uint32_t rotl(std::uint32_t x, int n) { return (x << n) | (x >> (32 - n)); }

// SHA-1 as specified in FIPS 180-4 section 6.1: 512-bit blocks, 80 rounds, big-endian.
Digest20 sha1(std::string_view data) {
  std::uint32_t h[5] = {0x67452301u, 0xEFCDAB89u, 0x98BADCFEu, 0x10325476u, 0xC3D2E1F0u};
  std::string message(data);
  const std::uint64_t bit_length = static_cast<std::uint64_t>(data.size()) * 8u;
  message.push_back(static_cast<char>(0x80));
  while (message.size() % 64 != 56) message.push_back('\0');
  for (int i = 7; i >= 0; --i) message.push_back(static_cast<char>((bit_length >> (i * 8)) & 0xFF));

  for (std::size_t block = 0; block < message.size(); block += 64) {
    std::uint32_t w[80];
    for (int t = 0; t < 16; ++t) {
      const auto* p = reinterpret_cast<const unsigned char*>(message.data() + block + 4 * t);
      w[t] = (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
             (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
    }
    for (int t = 16; t < 80; ++t) w[t] = rotl(w[t - 3] ^ w[t - 8] ^ w[t - 14] ^ w[t - 16], 1);
    std::uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4];
    for (int t = 0; t < 80; ++t) {
      std::uint32_t f, k;
      if (t < 20) {
        f = (b & c) | (~b & d);
        k = 0x5A827999u;
      } else if (t < 40) {
        f = b ^ c ^ d;
        k = 0x6ED9EBA1u;
      } else if (t < 60) {
        f = (b & c) | (b & d) | (c & d);
        k = 0x8F1BBCDCu;
      } else {
        f = b ^ c ^ d;
        k = 0xCA62C1D6u;
      }
      const std::uint32_t temp = rotl(a, 5) + f + e + k + w[t];
      e = d;
      d = c;
      c = rotl(b, 30);
      b = a;
      a = temp;
    }
    h[0] += a;
    h[1] += b;
    h[2] += c;
    h[3] += d;
    h[4] += e;
  }
  Digest20 digest{};
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) digest[4 * i + j] = static_cast<std::uint8_t>(h[i] >> (24 - 8 * j));
  }
  return digest;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string format_uuid(const Bytes16& b) {
  static const char* kHex = "0123456789abcdef";
  std::string out;
  out.reserve(36);
  for (int i = 0; i < 16; ++i) {
    if (i == 4 || i == 6 || i == 8 || i == 10) out.push_back('-');
    out.push_back(kHex[b[i] >> 4]);
    out.push_back(kHex[b[i] & 0xF]);
  }
  return out;
}

// RFC 4122 section 4.1.1/4.1.3: variant bits 10xx in byte 8, version in the high nibble of 6.
void stamp(Bytes16& b, int version) {
  b[6] = static_cast<std::uint8_t>((b[6] & 0x0F) | (version << 4));
  b[8] = static_cast<std::uint8_t>((b[8] & 0x3F) | 0x80);
}

}  // namespace

bool is_uuid(std::string_view text) {
  if (text.size() != 36) return false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (i == 8 || i == 13 || i == 18 || i == 23) {
      if (text[i] != '-') return false;
    } else if (hex_value(text[i]) < 0) {
      return false;
    }
  }
  return true;
}

std::string make_uuid_v4() {
  // 122 random bits straight from the kernel for every UUID: no generator state that a fork()
  // would copy into the child (two processes must never mint the same attempt id).
  Bytes16 b{};
  std::size_t filled = 0;
  while (filled < b.size()) {
    const ssize_t got = getrandom(b.data() + filled, b.size() - filled, 0);
    if (got <= 0) break;
    filled += static_cast<std::size_t>(got);
  }
  if (filled < b.size()) {
    // getrandom unavailable (very old kernel): fall back to std::random_device, per call.
    std::random_device device;
    for (std::size_t i = 0; i < b.size(); i += 4) {
      const std::uint32_t r = device();
      for (std::size_t j = 0; j < 4; ++j) b[i + j] = static_cast<std::uint8_t>(r >> (8 * j));
    }
  }
  stamp(b, 4);
  return format_uuid(b);
}

std::optional<std::string> make_uuid_v5(std::string_view namespace_uuid, std::string_view name) {
  if (!is_uuid(namespace_uuid)) return std::nullopt;
  // RFC 4122 section 4.3: SHA-1 over the namespace's 16 bytes followed by the name.
  std::string input;
  for (std::size_t i = 0; i < namespace_uuid.size(); ++i) {
    if (namespace_uuid[i] == '-') continue;
    const int hi = hex_value(namespace_uuid[i]);
    const int lo = hex_value(namespace_uuid[++i]);
    input.push_back(static_cast<char>((hi << 4) | lo));
  }
  input.append(name);
  const Digest20 digest = sha1(input);
  Bytes16 b{};
  for (int i = 0; i < 16; ++i) b[i] = digest[i];
  stamp(b, 5);
  return format_uuid(b);
}

std::string sha1_hex(std::string_view data) {
  static const char* kHex = "0123456789abcdef";
  const Digest20 digest = sha1(data);
  std::string out;
  for (std::uint8_t byte : digest) {
    out.push_back(kHex[byte >> 4]);
    out.push_back(kHex[byte & 0xF]);
  }
  return out;
}

}  // namespace acdr

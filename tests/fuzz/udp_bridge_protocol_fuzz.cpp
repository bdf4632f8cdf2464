// libFuzzer target: the UDP bridge's datagram decoder on any bytes. It must return without
// reading out of bounds; a datagram it accepts has its type's exact size and encodes back to
// a datagram that decodes to the same type and sequence.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "engine/devices/udp_bridge_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace acdr::bridge;
  Message m;
  std::string detail;
  const DecodeError e = decode(std::span<const std::uint8_t>(data, size), m, &detail);
  if (e != DecodeError::kNone) {
    if (detail.empty() || decode_error_name(e) == nullptr) std::abort();
    return 0;
  }
  if (size != message_size(m.type)) std::abort();
  std::array<std::uint8_t, 256> out{};
  const std::size_t n = encode(m, out);
  Message again;
  if (n != size || decode(std::span<const std::uint8_t>(out.data(), n), again) != DecodeError::kNone) std::abort();
  if (again.type != m.type || again.sequence != m.sequence) std::abort();
  return 0;
}

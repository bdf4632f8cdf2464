// Writes one encoded datagram of each bridge message type into the directory given, as the
// seed corpus of udp_bridge_protocol_fuzz (the protocol has no bundled files to start from).
#include <array>
#include <cstdint>
#include <fstream>
#include <string>

#include "engine/devices/udp_bridge_protocol.hpp"

int main(int argc, char** argv) {
  using namespace acdr::bridge;
  if (argc != 2) return 2;
  const MessageType types[] = {MessageType::kPose, MessageType::kForce, MessageType::kEndOfAttempt,
                               MessageType::kAttemptOver};
  for (MessageType type : types) {
    Message m;
    m.type = type;
    m.sequence = 7;
    m.timestamp_s = 1.25;
    m.pose.position = acdr::Vec3(0.01, -0.02, 0.11);
    m.force_N = acdr::Vec3(0.5, 0.0, -1.0);
    m.status = kStatusRunning;
    std::array<std::uint8_t, 256> out{};
    const std::size_t n = encode(m, out);
    std::ofstream(std::string(argv[1]) + "/type" + std::to_string(static_cast<int>(type)) + ".bin",
                  std::ios::binary)
        .write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(n));
  }
  return 0;
}

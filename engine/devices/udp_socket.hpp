// A small RAII wrapper over a POSIX UDP socket (IPv4), non-blocking, for the haptic bridge:
// the simulator binds a port on loopback and answers the bridge that opened the session; a bridge
// (or the virtual device) sends to that port. No allocation per packet.
#pragma once

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace acdr {

/// An IPv4 address and port.
struct UdpEndpoint {
  sockaddr_in address{};
  bool valid = false;

  /// "127.0.0.1:7000".
  std::string to_string() const;
  /// The same address and port (both valid).
  bool same_as(const UdpEndpoint& other) const {
    return valid && other.valid && address.sin_port == other.address.sin_port &&
           address.sin_addr.s_addr == other.address.sin_addr.s_addr;
  }
};

/// `host` as a dotted IPv4 address ("127.0.0.1") or "localhost", and `port`.
/// Returns an invalid endpoint when the host is not one of those.
UdpEndpoint make_endpoint(const std::string& host, int port);

class UdpSocket {
 public:
  /// Opens a non-blocking socket bound to host:port (port 0: the system picks one; see
  /// local_port()). Null and an error naming the address on failure (port in use, ...).
  static std::unique_ptr<UdpSocket> bind(const std::string& host, int port, std::string* error);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  int local_port() const { return port_; }

  /// Sends one datagram; false when the system refused it (the error is kept in last_error).
  bool send_to(const UdpEndpoint& to, std::span<const std::uint8_t> bytes);
  /// Receives one waiting datagram into `buffer`; returns its size, 0 when none is waiting,
  /// -1 on an error. A datagram longer than the buffer is reported with its full size (so the
  /// caller sees it as malformed) but only the buffer's worth is kept. `from` gets the sender.
  long receive(std::span<std::uint8_t> buffer, UdpEndpoint* from);
  /// Waits until a datagram is waiting or `timeout_s` passes; true if one is waiting.
  bool wait_readable(double timeout_s);

  const std::string& last_error() const { return last_error_; }

 private:
  UdpSocket() = default;
  int fd_ = -1;
  int port_ = 0;
  std::string last_error_;
};

}  // namespace acdr

// POSIX UDP socket.
#include "engine/devices/udp_socket.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace acdr {

std::string UdpEndpoint::to_string() const {
  if (!valid) return "(none)";
  char text[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &address.sin_addr, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(address.sin_port));
}

UdpEndpoint make_endpoint(const std::string& host, int port) {
  UdpEndpoint e;
  e.address.sin_family = AF_INET;
  e.address.sin_port = htons(static_cast<std::uint16_t>(port));
  const std::string h = host == "localhost" ? "127.0.0.1" : host;
  e.valid = port >= 0 && port <= 65535 && inet_pton(AF_INET, h.c_str(), &e.address.sin_addr) == 1;
  return e;
}

std::unique_ptr<UdpSocket> UdpSocket::bind(const std::string& host, int port,
                                           std::string* error) {
  const UdpEndpoint at = make_endpoint(host, port);
  if (!at.valid) {
    if (error)
      *error = "udp: bad address '" + host + ":" + std::to_string(port) +
               "' (expected a dotted IPv4 address or localhost, port 0-65535)";
    return nullptr;
  }
  std::unique_ptr<UdpSocket> s(new UdpSocket());
  s->fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (s->fd_ < 0) {
    if (error) *error = std::string("udp: socket(): ") + std::strerror(errno);
    return nullptr;
  }
  if (::bind(s->fd_, reinterpret_cast<const sockaddr*>(&at.address), sizeof at.address) != 0) {
    if (error)
      *error = "udp: cannot bind " + at.to_string() + ": " + std::strerror(errno) +
               (errno == EADDRINUSE ? " (another program uses this port; pick another)" : "");
    return nullptr;
  }
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  ::getsockname(s->fd_, reinterpret_cast<sockaddr*>(&bound), &len);
  s->port_ = ntohs(bound.sin_port);
  return s;
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpSocket::send_to(const UdpEndpoint& to, std::span<const std::uint8_t> bytes) {
  if (!to.valid) return false;
  const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), 0,
                             reinterpret_cast<const sockaddr*>(&to.address), sizeof to.address);
  if (n == static_cast<ssize_t>(bytes.size())) return true;
  last_error_ = std::string("sendto ") + to.to_string() + ": " + std::strerror(errno);
  return false;
}

long UdpSocket::receive(std::span<std::uint8_t> buffer, UdpEndpoint* from) {
  for (;;) {
    sockaddr_in sender{};
    socklen_t len = sizeof sender;
    // MSG_TRUNC: the return value is the datagram's real length, so an oversized packet is
    // seen as such rather than as a valid prefix.
    const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_TRUNC,
                                 reinterpret_cast<sockaddr*>(&sender), &len);
    if (n >= 0) {
      if (from) {
        from->address = sender;
        from->valid = true;
      }
      return static_cast<long>(n);
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) return 0;
    // A previous send to a closed port reports ECONNREFUSED here on Linux: not our datagram.
    if (errno == ECONNREFUSED || errno == EINTR) continue;
    last_error_ = std::string("recvfrom: ") + std::strerror(errno);
    return -1;
  }
}

bool UdpSocket::wait_readable(double timeout_s) {
  pollfd p{fd_, POLLIN, 0};
  const int ms = timeout_s <= 0 ? 0 : static_cast<int>(std::ceil(timeout_s * 1e3));
  return ::poll(&p, 1, ms) > 0 && (p.revents & POLLIN);
}

}  // namespace acdr

#include "engine/core/state_hash.hpp"

#include <cstdio>

namespace acdr {

std::string hash_hex(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace acdr

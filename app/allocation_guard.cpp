// Allocation failures turned into messages (see allocation_guard.hpp).
#include "app/allocation_guard.hpp"

#include <new>
#include <stdexcept>

namespace acdr {

std::string run_catching_allocation_failure(const std::function<void()>& body,
                                            const std::string& doing) {
  const std::string advice = "; the scenario needs more memory than this machine or its limits allow";
  try {
    body();
  } catch (const std::bad_alloc& e) {
    return "out of memory while " + doing + " (" + e.what() + advice + ")";
  } catch (const std::length_error& e) {
    return "out of memory while " + doing + " (a buffer would exceed its largest size: " + e.what() +
           advice + ")";
  }
  return {};
}

}  // namespace acdr

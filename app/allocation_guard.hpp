// Memory running out is bad input, not a crash: a scenario may ask for more than the machine
// (or an address-space limit) gives, and an uncaught std::bad_alloc would end the program with
// a signal and leave its attempt `running`. These guards turn the failure into a message the
// caller stores with the attempt and prints.
#pragma once

#include <functional>
#include <string>

namespace acdr {

/// Runs `body`. Returns "" when it finished, else what ran out: "out of memory while <doing>
/// (std::bad_alloc; the scenario needs more memory than this machine or its limits allow)".
/// Only allocation failures (std::bad_alloc, std::length_error) are caught; anything else
/// propagates.
std::string run_catching_allocation_failure(const std::function<void()>& body,
                                            const std::string& doing);

}  // namespace acdr

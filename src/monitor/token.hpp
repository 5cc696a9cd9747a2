// The monitor's control token (docs/monitor.md): printed by keel run at start, required by the
// emergency stop and clear; without it a client only watches.
// Thread-safety: plain functions.
#pragma once

#include <string>
#include <string_view>

#include "keel/result.hpp"

namespace keel::monitor {

/// 128 random bits from the kernel (getrandom), as 32 lowercase hex digits.
Result<std::string> newToken();

/// Whether `given` is `token`, in a time that does not depend on where they first differ.
bool tokenMatches(std::string_view token, std::string_view given);

}  // namespace keel::monitor

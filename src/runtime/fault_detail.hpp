// formatDetail: writes a FaultEvent's human-readable detail in place (truncated to fit, always
// terminated), without allocating — usable on a fault path. Shared by every detector.
// Thread-safety: touches only the given event.
#pragma once

#include <fmt/format.h>

#include <utility>

#include "keel/fault_event.hpp"

namespace keel::runtime {

template <class... Args>
void formatDetail(FaultEvent& ev, fmt::format_string<Args...> format, Args&&... args) {
  auto r = fmt::format_to_n(ev.detail.data(), ev.detail.size() - 1, format, std::forward<Args>(args)...);
  *r.out = '\0';
}

}  // namespace keel::runtime

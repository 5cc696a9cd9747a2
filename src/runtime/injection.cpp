#include "runtime/injection.hpp"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "runtime/component_core.hpp"

namespace keel::runtime {
namespace {

constexpr std::pair<std::string_view, InjectKind> kNames[] = {
    {"segfault", InjectKind::Segfault},     {"divide_by_zero", InjectKind::DivideByZero},
    {"abort", InjectKind::Abort},           {"throw", InjectKind::Throw},
    {"error_code", InjectKind::ErrorCode},  {"hang", InjectKind::Hang},
    {"stall_heartbeat", InjectKind::StallHeartbeat}, {"out_of_range", InjectKind::OutOfRange},
};

void markManifested(detail::ComponentCore& core) {
  core.injected_id.store(core.inject_id.load(std::memory_order_relaxed), std::memory_order_relaxed);
  core.injected_t_ns.store(steadyNs(), std::memory_order_release);
}

[[gnu::noinline]] void segfaultNow() {
  volatile std::uintptr_t addr = 0x10;  // page 0 is never mapped
  *reinterpret_cast<volatile int*>(addr) = 1;
}

[[gnu::noinline]] void divideByZeroNow() {
#if defined(__x86_64__)
  asm volatile("xor %%ecx, %%ecx\n\tmov $1, %%eax\n\tcltd\n\tidivl %%ecx" ::: "eax", "ecx", "edx");
#else
  std::raise(SIGFPE);
#endif
}

}  // namespace

std::int64_t steadyNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::optional<InjectKind> parseInjectKind(std::string_view name) {
  for (auto [n, k] : kNames)
    if (n == name) return k;
  return std::nullopt;
}

std::string_view toString(InjectKind k) {
  for (auto [n, kind] : kNames)
    if (kind == k) return n;
  return "none";
}

bool arm(Component& c, InjectKind kind, std::uint64_t fault_id, std::string_view port, double value) {
  detail::ComponentCore& core = coreOf(c);
  core.inject_id.store(fault_id, std::memory_order_relaxed);
  if (kind == InjectKind::OutOfRange) {
    for (detail::PortBase* p : core.ports) {
      if (p->kind() != detail::PortKind::Data || p->direction() != detail::PortDirection::Output ||
          !p->numeric() || (!port.empty() && p->name() != port))
        continue;
      static_cast<detail::OutputPortBase*>(p)->corruptNext(value);
      return true;
    }
    return false;
  }
  core.inject_kind.store(static_cast<std::uint8_t>(kind), std::memory_order_release);
  return true;
}

ReturnCode fire(Component& c, InjectKind kind) {
  detail::ComponentCore& core = coreOf(c);
  markManifested(core);
  switch (kind) {
    case InjectKind::Segfault: segfaultNow(); break;
    case InjectKind::DivideByZero: divideByZeroNow(); break;
    case InjectKind::Abort: std::abort();
    case InjectKind::Throw: throw std::runtime_error("injected exception");
    case InjectKind::ErrorCode: return ReturnCode::InternalFault;
    case InjectKind::Hang:
      for (;;) std::this_thread::sleep_for(std::chrono::milliseconds(1));  // interrupted by a signal only
    case InjectKind::StallHeartbeat:
      core.stalled_until_ns.store(std::numeric_limits<std::int64_t>::max(), std::memory_order_release);
      return ReturnCode::Ok;
    case InjectKind::OutOfRange:
    case InjectKind::None: break;
  }
  return ReturnCode::Ok;
}

}  // namespace keel::runtime

void keel::detail::noteInjectedCorruption(Component& owner) {
  keel::runtime::markManifested(keel::runtime::coreOf(owner));
}

#include "runtime/injection.hpp"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <thread>

#include "runtime/component_core.hpp"
#include "runtime/port_access.hpp"

namespace keel::runtime {
namespace {

constexpr std::pair<std::string_view, InjectKind> kNames[] = {
    {"segfault", InjectKind::Segfault},
    {"divide_by_zero", InjectKind::DivideByZero},
    {"abort", InjectKind::Abort},
    {"throw", InjectKind::Throw},
    {"error_code", InjectKind::ErrorCode},
    {"hang", InjectKind::Hang},
    {"stall_heartbeat", InjectKind::StallHeartbeat},
    {"out_of_range", InjectKind::OutOfRange},
    {"kill", InjectKind::Kill},
};

void markManifested(detail::ComponentCore& core) {
  core.injection.injected_id.store(core.injection.id.load(std::memory_order_relaxed), std::memory_order_relaxed);
  core.injection.injected_t_ns.store(steadyNs(), std::memory_order_release);
}

// The store faults before it happens; TSan would still see two threads "writing" the same
// address when two components are injected at once.
[[gnu::noinline]] __attribute__((no_sanitize("thread"))) void segfaultNow() {
  volatile std::uintptr_t addr = 0x10;         // page 0 is never mapped
  *reinterpret_cast<volatile int*>(addr) = 1;  // NOLINT(performance-no-int-to-ptr): the injected fault
}

[[gnu::noinline]] void divideByZeroNow() {
#if defined(__x86_64__)
  asm volatile("xor %%ecx, %%ecx\n\tmov $1, %%eax\n\tcltd\n\tidivl %%ecx" ::: "eax", "ecx", "edx");
#else
  std::raise(SIGFPE);
#endif
}

}  // namespace

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

detail::OutputPortBase* corruptiblePort(Component& c, std::string_view port) {
  for (detail::PortBase* p : coreOf(c).ports) {
    if (p->kind() == PortKind::Data && p->direction() == PortDirection::Output && p->numeric() &&
        (port.empty() || p->name() == port))
      return static_cast<detail::OutputPortBase*>(p);
  }
  return nullptr;
}

bool arm(Component& c, InjectKind kind, std::uint64_t fault_id, const InjectArgs& args) {
  detail::ComponentCore& core = coreOf(c);
  core.injection.id.store(fault_id, std::memory_order_relaxed);
  switch (kind) {
    case InjectKind::OutOfRange: {
      detail::OutputPortBase* p = corruptiblePort(c, args.port);
      return p != nullptr && detail::PortAccess::corruptNext(*p, args.value);
    }
    case InjectKind::Kill: {
      auto* target = dynamic_cast<ProcessTarget*>(&c);
      if (target == nullptr) return false;
      // The death before is not diagnosed yet (a loaded machine still handling it): this kill
      // would take its place in the injection record, and one death would lose its `injected`.
      if (core.injection.injected_id.load(std::memory_order_acquire) != 0) return false;
      markManifested(core);  // before the signal: its death may be detected at once
      if (target->signalProcess(SIGKILL)) return true;
      core.injection.injected_id.store(0, std::memory_order_release);  // no process to kill now
      return false;
    }
    case InjectKind::StallHeartbeat:
      if (c.state() != State::Active) return false;  // not running: it has no heartbeat to stall
      markManifested(core);
      core.injection.stalled_until_ns.store(args.duration_ns > 0 ? steadyNs() + args.duration_ns
                                                                 : std::numeric_limits<std::int64_t>::max(),
                                            std::memory_order_release);
      return true;
    default: core.injection.kind.store(static_cast<std::uint8_t>(kind), std::memory_order_release); return true;
  }
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
    case InjectKind::Hang:  // never returns by itself; keel ends it at shutdown
      while (!core.injection.release_hang.load(std::memory_order_acquire))
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      return ReturnCode::Ok;
    case InjectKind::StallHeartbeat:  // applied by arm()
    case InjectKind::Kill:
    case InjectKind::OutOfRange:
    case InjectKind::None: break;
  }
  return ReturnCode::Ok;
}

}  // namespace keel::runtime

namespace {
thread_local keel::detail::ComponentCore* t_in_flight = nullptr;
}

keel::detail::ComponentCore* keel::runtime::injectionInFlight() { return t_in_flight; }

void keel::detail::noteInjectedCorruption(Component& owner) {
  t_in_flight = &keel::runtime::coreOf(owner);
  keel::runtime::markManifested(*t_in_flight);
}

void keel::detail::endInjectedCorruption() { t_in_flight = nullptr; }

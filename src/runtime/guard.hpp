// Guarded invocation: runs one component callback so that whatever goes wrong inside becomes a
// value instead of taking the process down (paper §5.1.1). C++ exceptions are caught; a non-Ok
// return code is reported; SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT raised on this thread
// inside the callback jump back here (sigsetjmp/siglongjmp, the handler on the thread's
// sigaltstack). A signal outside any guarded call gets its default action (re-raised).
// What this cannot promise (docs/faults.md): memory or locks the callback held when it
// faulted are not released; a fault inside malloc or another lock-holding library call may
// leave that library unusable. Process isolation is the safe tier for such components.
// Thread-safety: each thread has its own guard frames.
#pragma once

#include <setjmp.h>

#include <pthread.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <exception>

#include "keel/fault_event.hpp"
#include "keel/return_code.hpp"

namespace keel {
class Component;
}

namespace keel::runtime {

struct GuardOutcome {
  enum class Kind : std::uint8_t { Ok, ErrorCode, Exception, Signal };
  Kind kind = Kind::Ok;
  ReturnCode rc = ReturnCode::Ok;
  int signo = 0;
  // The kernel's own signals (a fault: si_code > 0) carry the faulting address (SIGSEGV,
  // SIGBUS) or instruction (SIGFPE, SIGILL); a signal sent (abort(), raise(), kill) carries the
  // sender's pid instead, and its si_addr means nothing.
  bool sent = false;
  const void* addr = nullptr;
  int sender = 0;
  std::int64_t t_ns = 0;         // Signal, Exception: steady-clock ns when caught
  std::array<char, 120> what{};  // exception message (truncated)

  bool ok() const { return kind == Kind::Ok; }
  FaultKind faultKind() const;
  /// Fills `fault` (kind and detail) from this outcome; `callback` names where it happened.
  /// `code_name` names a returned code, when the component has names of its own for them.
  void describe(FaultEvent& fault, const char* callback, const char* (*code_name)(int) = nullptr) const;
};

namespace guard_detail {
struct GuardFrame {
  sigjmp_buf env;
  volatile int signo = 0;
  volatile bool sent = false;
  const void* volatile addr = nullptr;
  volatile int sender = 0;
  volatile std::int64_t t_ns = 0;
  const std::atomic<bool>* interrupt = nullptr;  // set: interruptSignal() ends this call
  Component* owner = nullptr;                    // whose callback this is (runningComponent)
  GuardFrame* prev = nullptr;
};
GuardFrame*& currentFrame() noexcept;  // this thread's innermost frame
/// At the catch: the time first (the moment of detection), then the message.
void recordException(GuardOutcome& out, const std::exception* e) noexcept;
}  // namespace guard_detail

/// Installs the process-wide handlers (idempotent). The engine calls it before any callback.
void installSignalHandlers();

/// Gives the calling thread an alternate signal stack, so that a stack overflow inside a
/// callback can still be caught. Executors call it when their thread starts.
void installAltStack();

/// The signal that interrupts a hung callback (a real-time signal keel reserves).
int interruptSignal();

/// Interrupts the guarded call running on `thread` if that call was made with an `interrupt`
/// flag that is now set: it ends as a Signal outcome with signo == interruptSignal(). A
/// thread outside such a call ignores the signal. Async: returns at once.
void interruptThread(pthread_t thread);

/// Runs `f` (returning ReturnCode) under the guard, as a callback of `owner` (may be null).
/// While `*interrupt` is set, the call can be ended from another thread with interruptThread().
template <class F>
[[gnu::noinline]] GuardOutcome guarded(F&& f, Component* owner = nullptr,
                                       const std::atomic<bool>* interrupt = nullptr) noexcept {
  GuardOutcome out;
  guard_detail::GuardFrame frame;
  frame.interrupt = interrupt;
  frame.owner = owner;
  guard_detail::GuardFrame*& top = guard_detail::currentFrame();
  frame.prev = top;
  top = &frame;
  if (sigsetjmp(frame.env, 0) == 0) {  // 0: do not save the mask (no syscall on this path)
    try {
      out.rc = f();
      if (out.rc != ReturnCode::Ok) out.kind = GuardOutcome::Kind::ErrorCode;
    } catch (const std::exception& e) {
      guard_detail::recordException(out, &e);
    } catch (...) {
      guard_detail::recordException(out, nullptr);
    }
  } else {
    out.kind = GuardOutcome::Kind::Signal;
    out.signo = frame.signo;
    out.sent = frame.sent;
    out.addr = frame.addr;
    out.sender = frame.sender;
    out.t_ns = frame.t_ns;
  }
  guard_detail::currentFrame() = frame.prev;
  return out;
}

}  // namespace keel::runtime

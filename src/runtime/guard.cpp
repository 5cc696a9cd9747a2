#include "runtime/guard.hpp"
#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"

#include "runtime/fault_detail.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <ctime>
#include <mutex>

namespace keel::runtime {
namespace {

constexpr int kCaught[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};

// initial-exec: libkeel is linked at start-up, and this is read inside a signal handler, where
// a lazily allocated TLS block would not be safe.
thread_local guard_detail::GuardFrame* t_frame __attribute__((tls_model("initial-exec"))) = nullptr;

// Under ThreadSanitizer our handler runs inside TSan's own, which the kernel entered with every
// signal blocked (TSan installs it with a full sa_mask): jumping out would leave them blocked on
// this thread, and its next SIGSEGV would kill the process. Unblock what we catch before the
// jump. Not needed otherwise (SA_NODEFER, empty sa_mask): no syscall on the normal fault path.
void unblockBeforeJump() {
#if defined(__SANITIZE_THREAD__)
  sigset_t set;
  sigemptyset(&set);
  for (int s : kCaught) sigaddset(&set, s);
  sigaddset(&set, interruptSignal());
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
#endif
}

void onSignal(int signo, siginfo_t* info, void*) {
  guard_detail::GuardFrame* frame = t_frame;
  if (frame == nullptr) {
    // Not inside a guarded callback: a framework bug or a foreign thread. Do not swallow it.
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(signo, &dfl, nullptr);
    raise(signo);
    return;
  }
  frame->t_ns = steadyNs();  // the moment of detection
  frame->signo = signo;
  frame->sent = info == nullptr || info->si_code <= 0;  // SI_USER, SI_TKILL, SI_QUEUE: sent
  frame->addr = frame->sent ? nullptr : info->si_addr;
  frame->sender = frame->sent && info ? info->si_pid : 0;
  unblockBeforeJump();
  siglongjmp(frame->env, 1);
}

// A hung callback is ended by a signal sent to its thread (docs/fault-handling.md). Outside a
// guarded call made interruptible, or once its flag is cleared, the signal is ignored: the
// callback returned by itself in the meantime.
void onInterrupt(int signo, siginfo_t*, void*) {
  guard_detail::GuardFrame* frame = t_frame;
  if (frame == nullptr || frame->interrupt == nullptr || !frame->interrupt->load(std::memory_order_acquire)) return;
  frame->t_ns = steadyNs();
  frame->signo = signo;
  frame->sent = true;
  frame->addr = nullptr;
  frame->sender = 0;
  unblockBeforeJump();
  siglongjmp(frame->env, 1);
}

const char* signalName(int signo) {
  switch (signo) {
    case SIGSEGV: return "SIGSEGV";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGABRT: return "SIGABRT";
    default: return signo == interruptSignal() ? "interrupt" : "signal";
  }
}

}  // namespace

guard_detail::GuardFrame*& guard_detail::currentFrame() noexcept { return t_frame; }

void guard_detail::recordException(GuardOutcome& out, const std::exception* e) noexcept {
  out.t_ns = steadyNs();
  out.kind = GuardOutcome::Kind::Exception;
  const char* what = e ? e->what() : "unknown exception (not derived from std::exception)";
  std::strncpy(out.what.data(), what, out.what.size() - 1);
  out.what.back() = '\0';
  // A refused property: its name and whole message kept on the component (off the hot path).
  const auto* refused = dynamic_cast<const PropertyError*>(e);
  Component* owner = t_frame != nullptr ? t_frame->owner : nullptr;
  if (refused != nullptr && owner != nullptr) {
    try {
      detail::ComponentCore& core = coreOf(*owner);
      core.refused_property = refused->property();
      core.refused_text = refused->what();
    } catch (...) {  // out of memory: the truncated message is still in `out`
    }
  }
}

FaultKind GuardOutcome::faultKind() const {
  switch (kind) {
    case Kind::Signal: return FaultKind::Signal;
    case Kind::Exception: return FaultKind::Exception;
    default: return FaultKind::ErrorCode;
  }
}

void GuardOutcome::describe(FaultEvent& fault, const char* callback, const char* (*code_name)(int)) const {
  fault.kind = faultKind();
  switch (kind) {
    case Kind::Signal:
      if (!sent) {
        // A fault: where it happened (SIGFPE's and SIGILL's si_addr is the instruction's).
        const bool at_instruction = signo == SIGFPE || signo == SIGILL;
        formatDetail(fault, "{} in {} ({} {})", signalName(signo), callback, at_instruction ? "instruction" : "address",
                     addr);
      } else if (sender == ::getpid()) {
        formatDetail(fault, "{} in {} (raised by its own process: abort(), raise() or kill)", signalName(signo),
                     callback);
      } else if (sender != 0) {
        formatDetail(fault, "{} in {} (sent by process {})", signalName(signo), callback, sender);
      } else {
        formatDetail(fault, "{} in {}", signalName(signo), callback);
      }
      break;
    case Kind::Exception: formatDetail(fault, "exception in {}: {}", callback, what.data()); break;
    case Kind::ErrorCode:
      formatDetail(fault, "{} returned {} ({})", callback, static_cast<int>(rc),
                   code_name ? code_name(static_cast<int>(rc)) : toString(rc));
      break;
    case Kind::Ok: formatDetail(fault, "{} ok", callback); break;
  }
}

void installSignalHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa {};
    sa.sa_sigaction = onSignal;
    sigemptyset(&sa.sa_mask);
    // NODEFER: the signal stays unblocked after we jump out of the handler, so no mask has to
    // be saved or restored on the fast path. ONSTACK: survive a stack overflow.
    sa.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_NODEFER;
    for (int s : kCaught) sigaction(s, &sa, nullptr);
    struct sigaction in {};
    in.sa_sigaction = onInterrupt;
    sigemptyset(&in.sa_mask);
    in.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_NODEFER;
    sigaction(interruptSignal(), &in, nullptr);
  });
}

int interruptSignal() { return SIGRTMIN + 6; }

void interruptThread(pthread_t thread) { pthread_kill(thread, interruptSignal()); }

void installAltStack() {
  thread_local struct AltStack {
    void* mem = nullptr;
    std::size_t size = 0;
    AltStack() = default;
    AltStack(const AltStack&) = delete;
    AltStack& operator=(const AltStack&) = delete;
    ~AltStack() {
      if (!mem) return;
      stack_t off{};
      off.ss_flags = SS_DISABLE;
      sigaltstack(&off, nullptr);
      munmap(mem, size);
    }
  } alt;
  if (alt.mem) return;
  alt.size = std::size_t{64} * 1024;
  alt.mem = mmap(nullptr, alt.size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (alt.mem == MAP_FAILED) {
    alt.mem = nullptr;
    return;
  }
  stack_t ss{};
  ss.ss_sp = alt.mem;
  ss.ss_size = alt.size;
  sigaltstack(&ss, nullptr);
}

}  // namespace keel::runtime

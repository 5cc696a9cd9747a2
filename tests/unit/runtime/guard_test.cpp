#include "runtime/guard.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

#include "runtime/injection.hpp"
#include "support/crash.hpp"

namespace keel::runtime {
namespace {

class Guard : public ::testing::Test {
 protected:
  void SetUp() override {
    installSignalHandlers();
    installAltStack();
  }
};

TEST_F(Guard, PassesOkThrough) {
  GuardOutcome out = guarded([] { return ReturnCode::Ok; });
  EXPECT_TRUE(out.ok());
}

TEST_F(Guard, ReportsANonOkReturnCode) {
  GuardOutcome out = guarded([] { return ReturnCode::InputOutOfRange; });
  EXPECT_EQ(out.kind, GuardOutcome::Kind::ErrorCode);
  EXPECT_EQ(out.rc, ReturnCode::InputOutOfRange);
  FaultEvent f;
  out.describe(f, "onExecute");
  EXPECT_EQ(f.kind, FaultKind::ErrorCode);
  EXPECT_EQ(std::string(f.detailText()), "onExecute returned 402 (input out of range)");
}

TEST_F(Guard, CatchesAnExceptionWithItsMessage) {
  GuardOutcome out = guarded([]() -> ReturnCode { throw std::runtime_error("sensor gone"); });
  EXPECT_EQ(out.kind, GuardOutcome::Kind::Exception);
  FaultEvent f;
  out.describe(f, "onExecute");
  EXPECT_EQ(std::string(f.detailText()), "exception in onExecute: sensor gone");
}

TEST_F(Guard, CatchesAnExceptionNotDerivedFromStdException) {
  GuardOutcome out = guarded([]() -> ReturnCode { throw 42; });
  EXPECT_EQ(out.kind, GuardOutcome::Kind::Exception);
}

// The detection time is taken where it is caught: after the throw, before the guard returns.
TEST_F(Guard, StampsAFaultWithTheMomentItWasCaught) {
  std::int64_t thrown = 0, faulted = 0;
  GuardOutcome ex = guarded([&thrown]() -> ReturnCode {
    thrown = steadyNs();
    throw std::runtime_error("late");
  });
  const std::int64_t ex_returned = steadyNs();
  GuardOutcome sig = guarded([&faulted] {
    faulted = steadyNs();
    test::segfault();
    return ReturnCode::Ok;
  });
  const std::int64_t sig_returned = steadyNs();
  ASSERT_EQ(ex.kind, GuardOutcome::Kind::Exception);
  EXPECT_GE(ex.t_ns, thrown);
  EXPECT_LE(ex.t_ns, ex_returned);
  ASSERT_EQ(sig.kind, GuardOutcome::Kind::Signal);
  EXPECT_GE(sig.t_ns, faulted);
  EXPECT_LE(sig.t_ns, sig_returned);
  EXPECT_EQ(guarded([] { return ReturnCode::Ok; }).t_ns, 0) << "nothing caught, nothing stamped";
}

TEST_F(Guard, CatchesASegmentationFault) {
  GuardOutcome out = guarded([] {
    test::segfault();
    return ReturnCode::Ok;
  });
  ASSERT_EQ(out.kind, GuardOutcome::Kind::Signal);
  EXPECT_EQ(out.signo, SIGSEGV);
  EXPECT_EQ(out.addr, reinterpret_cast<const void*>(0x10));
  FaultEvent f;
  out.describe(f, "onExecute");
  EXPECT_EQ(f.kind, FaultKind::Signal);
  EXPECT_NE(std::string(f.detailText()).find("SIGSEGV in onExecute"), std::string::npos);
}

TEST_F(Guard, CatchesADivideByZero) {
  GuardOutcome out = guarded([] {
    test::divideByZero();
    return ReturnCode::Ok;
  });
  ASSERT_EQ(out.kind, GuardOutcome::Kind::Signal);
  EXPECT_EQ(out.signo, SIGFPE);
}

TEST_F(Guard, CatchesAbort) {
  GuardOutcome out = guarded([]() -> ReturnCode { std::abort(); });
  ASSERT_EQ(out.kind, GuardOutcome::Kind::Signal);
  EXPECT_EQ(out.signo, SIGABRT);
  // Sent (tgkill), not a fault: no address, which would be the sender's pid and uid read as one.
  FaultEvent fault;
  out.describe(fault, "onExecute");
  EXPECT_EQ(std::string(fault.detailText()),
            "SIGABRT in onExecute (raised by its own process: abort(), raise() or kill)");
}

TEST_F(Guard, AFaultsDetailGivesItsAddressAndASignalSentByAnotherProcessItsSender) {
  GuardOutcome segv = guarded([] {
    test::segfault();
    return ReturnCode::Ok;
  });
  FaultEvent fault;
  segv.describe(fault, "onExecute");
  EXPECT_EQ(std::string(fault.detailText()), "SIGSEGV in onExecute (address 0x10)");

  // Another process's kill -ABRT at this thread: a child, once the parent knows its pid.
  const pid_t self = ::getpid();
  const auto tid = static_cast<pid_t>(::syscall(SYS_gettid));
  int go[2];
  ASSERT_EQ(::pipe(go), 0);
  volatile pid_t child = 0;
  GuardOutcome sent = guarded([&]() -> ReturnCode {
    const pid_t c = ::fork();
    if (c == 0) {
      char byte = 0;
      if (::read(go[0], &byte, 1) == 1) ::syscall(SYS_tgkill, self, tid, SIGABRT);
      ::_exit(0);
    }
    child = c;
    const char byte = 1;
    if (::write(go[1], &byte, 1) != 1) return ReturnCode::PreconditionNotMet;
    for (;;) ::pause();  // until the signal arrives
  });
  ::close(go[0]);
  ::close(go[1]);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  ASSERT_EQ(sent.kind, GuardOutcome::Kind::Signal);
  FaultEvent from_other;
  sent.describe(from_other, "onExecute");
  EXPECT_EQ(std::string(from_other.detailText()),
            "SIGABRT in onExecute (sent by process " + std::to_string(child) + ")");
}

TEST_F(Guard, KeepsCatchingAfterManyFaultsOnOneThread) {
  for (int i = 0; i < 200; ++i) {
    GuardOutcome out = guarded([] {
      test::segfault();
      return ReturnCode::Ok;
    });
    ASSERT_EQ(out.signo, SIGSEGV) << "iteration " << i;
  }
  EXPECT_TRUE(guarded([] { return ReturnCode::Ok; }).ok());
}

TEST_F(Guard, NestedGuardsReportToTheInnermost) {
  GuardOutcome inner;
  GuardOutcome outer = guarded([&inner] {
    inner = guarded([] {
      test::segfault();
      return ReturnCode::Ok;
    });
    return ReturnCode::Ok;
  });
  EXPECT_EQ(inner.signo, SIGSEGV);
  EXPECT_TRUE(outer.ok());
}

TEST_F(Guard, CatchesOnEveryThread) {
  GuardOutcome out;
  std::thread t([&out] {
    installAltStack();
    out = guarded([] {
      test::segfault();
      return ReturnCode::Ok;
    });
  });
  t.join();
  EXPECT_EQ(out.signo, SIGSEGV);
}

using GuardDeathTest = Guard;

TEST_F(GuardDeathTest, ASignalOutsideAGuardedCallIsNotSwallowed) {
  EXPECT_DEATH(
      {
        installSignalHandlers();
        test::segfault();
      },
      "");
}

}  // namespace
}  // namespace keel::runtime

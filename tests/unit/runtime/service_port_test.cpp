#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "keel/component.hpp"
#include "runtime/executor.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"
#include "support/recording_hooks.hpp"

namespace keel::runtime {
namespace {

using namespace std::chrono_literals;

class Calculator : public Component {
 public:
  ProvidedServicePort<double(double, double)> add{this, "add", [this](double a, double b) {
                                                    thread = std::this_thread::get_id();
                                                    return a + b;
                                                  }};
  ProvidedServicePort<int(int)> slow{this, "slow", [](int x) {
                                       std::this_thread::sleep_for(300ms);
                                       return x;
                                     }};
  ProvidedServicePort<void(int)> crash{this, "crash", [](int) { throw std::runtime_error("boom"); }};
  std::atomic<std::thread::id> thread{};
};

class Client : public Component {
 public:
  RequiredServicePort<double(double, double)> add{this, "add"};
  RequiredServicePort<int(int)> slow{this, "slow"};
  RequiredServicePort<void(int)> crash{this, "crash"};
  RequiredServicePort<int(int, int)> wrong{this, "wrong"};
};

/// Binds as the runtime does, through the ports' runtime side.
bool bind(detail::ServicePortBase& required, detail::ServicePortBase& provided) { return required.bind(provided); }

class ServicePortTest : public ::testing::Test {
 protected:
  void SetUp() override {
    installSignalHandlers();
    test::manage(calc_, "calc", hooks_);
    test::manage(client_, "client", hooks_);
    ASSERT_TRUE(transition(calc_, Transition::Initialize));
    ASSERT_TRUE(bind(client_.add, calc_.add));
    ASSERT_TRUE(bind(client_.slow, calc_.slow));
    ASSERT_TRUE(bind(client_.crash, calc_.crash));
  }
  void TearDown() override {
    ex_.requestStop();
    ASSERT_TRUE(ex_.join(5s));
  }
  test::RecordingHooks hooks_;
  Calculator calc_;
  Client client_;
  Executor ex_{{"calc", ExecutorKind::Periodic, 10ms, 0, SchedPolicy::Other}};
};

TEST_F(ServicePortTest, ACallRunsOnTheProvidersExecutorAndReturnsTheResult) {
  ex_.add(calc_);
  ex_.start();
  auto r = client_.add.call(2.0, 3.5);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(*r, 5.5);
  EXPECT_NE(calc_.thread.load(), std::this_thread::get_id());
}

TEST_F(ServicePortTest, ASlowProviderTimesOutTheCall) {
  ex_.add(calc_);
  ex_.start();
  auto r = client_.slow.callWithin(20ms, 1);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("service 'slow' of 'calc': no answer within 20 ms"), std::string::npos)
      << r.error().message;
}

TEST_F(ServicePortTest, AProviderThatThrowsFaultsAndTheCallerGetsAnError) {
  ex_.add(calc_);
  ex_.start();
  auto r = client_.crash.call(1);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("faulted: exception in service call: boom"), std::string::npos) << r.error().message;
  EXPECT_EQ(calc_.state(), State::Error);
  ASSERT_EQ(hooks_.faults().size(), 1u);
  EXPECT_EQ(hooks_.faults()[0].kind, FaultKind::Exception);
}

TEST_F(ServicePortTest, ACallToAProviderThatIsNotActiveFails) {
  auto r = client_.add.call(1.0, 2.0);  // executor not started: calc is Ready
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("provider is Ready, not Active"), std::string::npos) << r.error().message;
}

TEST_F(ServicePortTest, AnUnconnectedPortFailsClearly) {
  auto r = client_.wrong.call(1, 2);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "service port 'wrong' is not connected");
}

TEST_F(ServicePortTest, ABindIsRefusedUnlessTheOtherSideProvidesTheSameSignature) {
  EXPECT_FALSE(bind(client_.wrong, calc_.add)) << "int(int, int) bound to double(double, double)";
  EXPECT_FALSE(bind(client_.wrong, client_.wrong)) << "a required port is no provider";
  // Refused, the port is as unconnected as before: a call says so, nothing reaches a provider.
  EXPECT_FALSE(client_.wrong.connected());
  auto r = client_.wrong.call(1, 2);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "service port 'wrong' is not connected");
  // And a bound port keeps its provider when a bind of another signature is refused.
  EXPECT_FALSE(bind(client_.add, client_.wrong));
  ASSERT_TRUE(transition(calc_, Transition::Start));
  auto sum = client_.add.call(1.0, 2.0);
  ASSERT_TRUE(sum) << sum.error().message;
  EXPECT_EQ(*sum, 3.0);
}

TEST_F(ServicePortTest, APassiveProviderRunsOnTheCallersThread) {
  ASSERT_TRUE(transition(calc_, Transition::Start));  // passive: no executor
  auto r = client_.add.call(1.0, 1.0);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(*r, 2.0);
  EXPECT_EQ(calc_.thread.load(), std::this_thread::get_id());
}

}  // namespace
}  // namespace keel::runtime

// The author's headers hold what an author calls (docs/decisions/0010): a component can push,
// pop and call through its ports, but cannot reach the runtime's side of them (queues,
// connections, validity, injection), and the two opt-in abilities are absent from a plain
// Component. Checked at compile time (an access violation makes a requires-expression false),
// then the runtime's side is shown to work through the bases it is reached by.
#include <gtest/gtest.h>

#include <memory>
#include <string_view>
#include <vector>

#include "keel/component.hpp"
#include "keel/hardware_driver.hpp"
#include "keel/run_control.hpp"
#include "runtime/port_access.hpp"
#include "support/recording_hooks.hpp"

namespace keel {
namespace {

// ---- what an author can call ----
template <class P>
concept Pushes = requires(P& p) {
  p.push(1.0);
};
template <class P>
concept Pops = requires(P& p) {
  p.pop();
  p.peek();
  p.empty();
};
template <class P>
concept Calls = requires(P& p) {
  p.call(1);
  p.connected();
};

// ---- the runtime's side ----
template <class P>
concept ConfiguresQueue = requires(P& p) {
  p.configureQueue(QueuePolicy::Fifo, 4);
};
template <class P>
concept Clears = requires(P& p) {
  p.clear();
};
template <class P>
concept CountsQueue = requires(P& p) {
  p.queued();
  p.dropped();
  p.capacity();
};
template <class P>
concept MakesConnections = requires(P& p) {
  p.makeConnection();
};
template <class P>
concept Attaches = requires(P& p, detail::ConnectionBase& c) {
  p.attach(c);
};
template <class P>
concept SetsValidity = requires(P& p) {
  p.setValidity(nullptr);
};
template <class P>
concept Corrupts = requires(P& p) {
  p.corruptNext(1.0);
};
template <class P>
concept TakesNext = requires(P& p) {
  p.takeNext();
};
template <class P>
concept Binds = requires(P& p, detail::ServicePortBase& s) {
  p.bind(s);
};
template <class P>
concept SetsTimeout = requires(P& p) {
  p.setTimeout(std::chrono::nanoseconds(1));
};

static_assert(Pushes<OutputDataPort<double>> && Pushes<OutputEventPort<double>>);
static_assert(Pops<InputDataPort<double>>);
static_assert(Calls<RequiredServicePort<int(int)>>);

static_assert(!ConfiguresQueue<InputDataPort<double>> && !ConfiguresQueue<InputEventPort<>>);
static_assert(!Clears<InputDataPort<double>> && !Clears<InputEventPort<>>);
static_assert(!CountsQueue<InputDataPort<double>> && !CountsQueue<InputEventPort<>>);
static_assert(!MakesConnections<InputDataPort<double>> && !MakesConnections<InputEventPort<>>);
static_assert(!Attaches<OutputDataPort<double>> && !Attaches<OutputEventPort<>>);
static_assert(!SetsValidity<InputDataPort<double>> && !SetsValidity<OutputDataPort<double>>);
static_assert(!Corrupts<OutputDataPort<double>> && !Corrupts<OutputEventPort<double>>);
static_assert(!TakesNext<InputEventPort<>> && !TakesNext<InputEventPortBase>);
static_assert(!Binds<RequiredServicePort<int(int)>> && !SetsTimeout<RequiredServicePort<int(int)>>);

template <class C>
concept HasHardwareFault = requires(C& c) {
  c.onHardwareFault(std::string_view{});
};
static_assert(!HasHardwareFault<Component>, "onHardwareFault is opt-in: keel::HardwareDriver");
static_assert(!std::is_base_of_v<RunControl, Component>, "endRun is opt-in: keel::RunControl");

class Source : public Component {
 public:
  OutputDataPort<double> out{this, "out"};
  OutputEventPort<int> events{this, "events"};
};

class Sink : public Component {
 public:
  InputDataPort<double> in{this, "in"};
  InputEventPort<int> events{this, "events"};
};

TEST(AuthorApi, TheRuntimeSideOfPortsWorksThroughTheBasesItIsReachedBy) {
  Source source;
  Sink sink;
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep;
  test::wire(source.out, sink.in, keep);
  test::wire(source.events, sink.events, keep);
  test::configureQueue(sink.in, QueuePolicy::Last, 8);

  source.out.push(1.0);
  source.out.push(2.0);
  source.events.send(7);
  detail::InputPortBase& in = sink.in;
  EXPECT_EQ(in.capacity(), 1u);  // LAST
  EXPECT_EQ(in.queued(), 1u);
  EXPECT_EQ(in.dropped(), 1u);
  EXPECT_EQ(sink.in.pop(), 2.0);

  ASSERT_TRUE(detail::PortAccess::takeNext(sink.events));
  EXPECT_EQ(sink.events.current(), 7);
  EXPECT_FALSE(detail::PortAccess::takeNext(sink.events));
}

TEST(AuthorApi, OnlyANumericDataOutputCanCarryAnInjectedCorruption) {
  Source source;
  EXPECT_FALSE(detail::PortAccess::corruptNext(source.events, 9.0));
  Sink sink;
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep;
  test::wire(source.out, sink.in, keep);
  ASSERT_TRUE(detail::PortAccess::corruptNext(source.out, 9.0));
  source.out.push(1.0);
  source.out.push(2.0);
  EXPECT_EQ(sink.in.pop(), 9.0);  // the next value only
  EXPECT_EQ(sink.in.pop(), 2.0);
}

}  // namespace
}  // namespace keel

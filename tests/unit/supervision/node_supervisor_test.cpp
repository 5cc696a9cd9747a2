// The node supervisor (src/supervision/node_supervisor.hpp) with plain programs as nodes: what
// a node is started with, its death as a `process` fault with its status and last lines, its
// restart and stop, and that none outlives the supervisor. (Real rclpy nodes: tests/integration.)
#include "supervision/node_supervisor.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "keel/msg/lifecycle_msgs/msg/state.hpp"
#include "keel/msg/lifecycle_msgs/msg/transition.hpp"
#include "runtime/injection.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/temp_log.hpp"

namespace keel::supervision {
namespace {

namespace fs = std::filesystem;

// One node, `/bin/sh -c SCRIPT` run as /demo/talker, in a plan of its own.
struct Rig {
  // `adjust` changes the node's profile before the supervisor reads it.
  explicit Rig(const std::string& script, double grace_ms = 2000,
               const std::function<void(profile::NodeProfile&)>& adjust = {})
      : dir(fs::temp_directory_path() / ("keel_node_sup_" + std::to_string(::getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    node.file = (dir / "talker.xml").string();
    node.name = "Talker";
    node.command = {"/bin/sh", "-c", script};
    node.executable = "/bin/sh";
    node.node_namespace = "/demo";
    node.node_name = "talker";
    node.environment = {{"KEEL_TEST_VAR", "from the profile", {}}, {"RCUTILS_COLORIZED_OUTPUT", "1", {}}};
    node.parameters = {{"speed", "0.2", {}}, {"mode", "fast", {}}};
    node.stop_grace_ms = grace_ms;
    node.component.name = "Talker";
    if (adjust) adjust(node);
    plan::PlannedInstance pi;
    pi.name = "talker";
    pi.profile = &node.component;
    pi.node = &node;
    plan.instances.push_back(pi);
    NodeLaunch launch{KEEL_NODE_EXEC, dir.string(), "run", 7};
    sup = std::make_unique<NodeSupervisor>(
        plan, launch, [this](const std::string& m) { warnings.push_back(m); }, log.log, spawner);
    proxy = sup->makeProxy(plan.instances.front());
    sup->setReport([this](Component&, const FaultEvent& f) {
      std::lock_guard lock(mutex);
      faults.push_back(f);
      changed.notify_all();
    });
  }
  ~Rig() {
    sup.reset();  // before the proxy, as the engine closes its side before its instances end
    fs::remove_all(dir);
  }
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;
  Rig(Rig&&) = delete;
  Rig& operator=(Rig&&) = delete;
  std::string output() const {
    std::ifstream in(sup->outputOf("talker"));
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  // Bounds against a hang, not speed goals.
  bool waitForOutput(const std::string& text) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (output().find(text) == std::string::npos) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
  }
  bool waitForFault() {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(30), [&] { return !faults.empty(); });
  }
  std::vector<nlohmann::json> nodeRecords() const { return test::eventsOf(log.read(), "node"); }

  fs::path dir;
  profile::NodeProfile node;
  plan::Plan plan;
  test::TempLog log{"keel_node_sup_log"};
  std::vector<std::string> warnings;
  Spawner spawner;
  std::unique_ptr<NodeSupervisor> sup;
  std::unique_ptr<Component> proxy;
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<FaultEvent> faults;
};

bool gone(pid_t pid) { return ::kill(pid, 0) != 0 && errno == ESRCH; }

TEST(NodeSupervisor, ANodeGetsItsRosNameParametersKeelsDomainAndItsEnvironmentInItsFolder) {
  Rig rig(
      R"sh(echo "args: $*"; echo "domain=$ROS_DOMAIN_ID var=$KEEL_TEST_VAR colour=$RCUTILS_COLORIZED_OUTPUT unbuffered=$PYTHONUNBUFFERED"; echo "in $(pwd)"; exec sleep 60)sh");
  ASSERT_TRUE(rig.sup->launch());
  ASSERT_TRUE(rig.waitForOutput("in "));
  EXPECT_EQ(rig.output(),
            "args: -r __node:=talker -r __ns:=/demo -p speed:=0.2 -p mode:=fast\n"  // $0 is --ros-args
            "domain=7 var=from the profile colour=1 unbuffered=1\n"
            "in " +
                rig.dir.string() + "\n");
  EXPECT_EQ(rig.sup->outputOf("talker"), (rig.dir / "run.talker.out").string());
  const pid_t pid = rig.sup->pidOf("talker");
  ASSERT_GT(pid, 0);
  EXPECT_EQ(::getpgid(pid), pid) << "not in a process group of its own";
  auto records = rig.nodeRecords();
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0]["phase"], "started");
  EXPECT_EQ(records[0]["component"], "talker");
  EXPECT_EQ(records[0]["node"], "/demo/talker");
  EXPECT_EQ(records[0]["pid"], pid);
}

TEST(NodeSupervisor, ItsDeathIsAProcessFaultWithItsExitStatusAndLastLines) {
  Rig rig("echo starting; echo 'cannot open /dev/ttyUSB0' >&2; exit 3");
  ASSERT_TRUE(rig.sup->launch());
  ASSERT_TRUE(rig.waitForFault());
  const pid_t pid = rig.nodeRecords().at(0)["pid"];
  {
    std::lock_guard lock(rig.mutex);
    ASSERT_EQ(rig.faults.size(), 1u);
    EXPECT_EQ(rig.faults[0].kind, FaultKind::Process);
    EXPECT_EQ(rig.faults[0].componentName(), "talker");
    EXPECT_EQ(rig.faults[0].detailText(),
              "node '/demo/talker' (pid " + std::to_string(pid) + ") exited with status 3: cannot open /dev/ttyUSB0");
    EXPECT_GT(rig.faults[0].t_ns, 0);
  }
  auto records = rig.nodeRecords();
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[1]["phase"], "exited");
  EXPECT_EQ(records[1]["detail"], "exited with status 3");
  EXPECT_EQ(records[1]["last_lines"], (nlohmann::json{"starting", "cannot open /dev/ttyUSB0"}));
  EXPECT_EQ(rig.sup->pidOf("talker"), 0);
}

TEST(NodeSupervisor, AKilledNodeIsAProcessFaultNamingTheSignal) {
  Rig rig("echo up; exec sleep 60");
  ASSERT_TRUE(rig.sup->launch());
  ASSERT_TRUE(rig.waitForOutput("up"));
  auto* target = dynamic_cast<runtime::ProcessTarget*>(rig.proxy.get());
  ASSERT_NE(target, nullptr);
  ASSERT_TRUE(target->signalProcess(SIGKILL));  // what an injected `kill` does
  ASSERT_TRUE(rig.waitForFault());
  std::lock_guard lock(rig.mutex);
  EXPECT_NE(std::string(rig.faults[0].detailText()).find(") killed by signal 9 (SIGKILL): up"), std::string::npos)
      << rig.faults[0].detailText();
}

TEST(NodeSupervisor, AResetRestartsALiveNodeAsANewProcessAndAStopEndsItWithoutAFault) {
  Rig rig("echo up; exec sleep 60");
  ASSERT_TRUE(rig.sup->launch());
  const pid_t first = rig.sup->pidOf("talker");
  ASSERT_TRUE(rig.waitForOutput("up"));
  EXPECT_EQ(rig.proxy->onReset(), ReturnCode::Ok);
  const pid_t second = rig.sup->pidOf("talker");
  EXPECT_GT(second, 0);
  EXPECT_NE(second, first);
  EXPECT_TRUE(gone(first));
  EXPECT_EQ(rig.proxy->onStop(), ReturnCode::Ok);
  EXPECT_EQ(rig.sup->pidOf("talker"), 0);
  EXPECT_TRUE(gone(second));
  std::vector<std::string> phases;
  for (const auto& r : rig.nodeRecords()) phases.push_back(r["phase"]);
  EXPECT_EQ(phases, (std::vector<std::string>{"started", "stopped", "restarted", "stopped"}));
  std::lock_guard lock(rig.mutex);
  EXPECT_TRUE(rig.faults.empty()) << "a stop keel asked for was taken for a fault: " << rig.faults[0].detailText();
}

TEST(NodeSupervisor, ARunEmptiesItsNodesOutputFileFirstAndItsRestartsAppendToIt) {
  Rig rig("echo \"life $$\"; exec sleep 60");
  { std::ofstream(rig.dir / "run.talker.out") << "a line of an earlier run\n"; }
  ASSERT_TRUE(rig.sup->launch());
  const pid_t first = rig.sup->pidOf("talker");
  ASSERT_TRUE(rig.waitForOutput("life " + std::to_string(first)));
  EXPECT_EQ(rig.proxy->onReset(), ReturnCode::Ok);
  const pid_t second = rig.sup->pidOf("talker");
  ASSERT_TRUE(rig.waitForOutput("life " + std::to_string(second)));
  EXPECT_EQ(rig.output(), fmt::format("life {}\nlife {}\n", first, second));
  EXPECT_EQ(rig.proxy->onStop(), ReturnCode::Ok);
}

TEST(NodeSupervisor, ANodeEndsAtSigintAndOneThatIgnoresItIsKilledAfterItsGrace) {
  {
    Rig polite("trap 'echo bye; exit 0' INT; echo ready; while :; do sleep 0.05; done");
    ASSERT_TRUE(polite.sup->launch());
    ASSERT_TRUE(polite.waitForOutput("ready"));
    EXPECT_EQ(polite.proxy->onStop(), ReturnCode::Ok);
    EXPECT_TRUE(polite.waitForOutput("bye"));
    EXPECT_EQ(polite.nodeRecords().back()["detail"], "exited with status 0");
  }
  Rig stubborn("trap '' INT; echo ready; while :; do sleep 0.05; done", 300);
  ASSERT_TRUE(stubborn.sup->launch());
  ASSERT_TRUE(stubborn.waitForOutput("ready"));
  EXPECT_EQ(stubborn.proxy->onStop(), ReturnCode::Ok);
  auto last = stubborn.nodeRecords().back();
  EXPECT_EQ(last["phase"], "stopped");
  EXPECT_EQ(last["detail"], "killed by signal 9 (SIGKILL)");
}

TEST(NodeSupervisor, NoNodeNorWhatItForkedOutlivesTheSupervisor) {
  // What it forked ignores SIGINT: only the SIGKILL to the node's group after its exit ends it.
  Rig rig("(trap '' INT; exec sleep 60) & echo \"child $!\"; wait");
  ASSERT_TRUE(rig.sup->launch());
  ASSERT_TRUE(rig.waitForOutput("child "));
  const pid_t node = rig.sup->pidOf("talker");
  const std::string out = rig.output();
  const pid_t forked = static_cast<pid_t>(std::stol(out.substr(out.find("child ") + 6)));
  ExitWatch watch;  // the forked sleep is not this process's child: seen ending, not reaped
  std::mutex m;
  std::condition_variable cv;
  bool forked_ended = false;
  ASSERT_TRUE(watch.watch(forked, [&](pid_t, const Exit&) {
    std::lock_guard lock(m);
    forked_ended = true;
    cv.notify_all();
  }));
  rig.sup.reset();
  EXPECT_TRUE(gone(node));
  std::unique_lock lock(m);
  EXPECT_TRUE(cv.wait_for(lock, std::chrono::seconds(30), [&] { return forked_ended; }))
      << "what the node forked outlived it";
}

TEST(NodeSupervisor, ANodeThatCannotBeStartedIsALaunchErrorAndOneThatCannotExecIsAFaultSayingWhy) {
  {
    Rig rig("exit 0");
    fs::remove_all(rig.dir);  // no folder for its output
    auto launched = rig.sup->launch();
    ASSERT_FALSE(launched);
    EXPECT_EQ(launched.error().message, "node 'talker': cannot open '" + (rig.dir / "run.talker.out").string() +
                                            "' for the output of '/bin/sh': No such file or directory");
  }
  Rig rig("exit 0");
  rig.node.executable = (rig.dir / "no-such-node").string();  // the shim starts, its exec fails
  ASSERT_TRUE(rig.sup->launch());
  ASSERT_TRUE(rig.waitForFault());
  std::lock_guard lock(rig.mutex);
  EXPECT_NE(std::string(rig.faults[0].detailText()).find("exited with status 127: keel-node-exec: cannot execute"),
            std::string::npos)
      << rig.faults[0].detailText();
}

// A node whose profile declares output topic /demo/chatter, started late unless seen in time.
void chatterNode(profile::NodeProfile& node) {
  node.topics = {{"chatter", "/demo/chatter", profile::DdsQos::Default, std::nullopt, std::nullopt, std::nullopt, {}}};
  profile::DataPort port;
  port.name = "chatter";
  port.usage = PortDirection::Output;
  port.data_type = "std_msgs/msg/String";
  node.component.data_ports = {port};
  node.start_timeout_ms = 300;
}

TEST(NodeSupervisor, ANodeIsUpWhenItsOwnProcessPublishesItsTopicsNotWhenAnotherDoes) {
  Rig rig("exec sleep 60", 2000, chatterNode);
  rig.node.start_timeout_ms = 60000;  // no start fault here
  ASSERT_TRUE(rig.sup->launch());
  const pid_t pid = rig.sup->pidOf("talker");
  // An earlier life (or anyone else) listing the name and publishing the topic is not it, nor is
  // its own process before it publishes.
  rig.sup->nodeSeen("talker", {{pid + 100000, true, {}}, {pid, true, {"/demo/chatter"}}});
  auto phases = [&] {
    std::vector<std::string> out;
    for (const auto& r : rig.nodeRecords()) out.push_back(r["phase"]);
    return out;
  };
  EXPECT_EQ(phases(), std::vector<std::string>{"started"});
  // Its own process publishing: up, though its name is not listed yet (a Fast DDS node's
  // listing can come seconds after its writers).
  rig.sup->nodeSeen("talker", {{pid + 100000, true, {}}, {pid, false, {}}});
  ASSERT_EQ(phases(), (std::vector<std::string>{"started", "up"}));
  const auto up = rig.nodeRecords().back();
  EXPECT_EQ(up["pid"], pid);
  EXPECT_GE(up["after_ms"].get<double>(), 0.0);
  rig.sup->nodeSeen("talker", {{pid, true, {}}});  // still up: no second record
  EXPECT_EQ(phases().size(), 2u);
  std::lock_guard lock(rig.mutex);
  EXPECT_TRUE(rig.faults.empty());
}

TEST(NodeSupervisor, ANodeNotUpWithinItsStartTimeoutIsAStartFaultSayingWhatWasMissing) {
  Rig rig("exec sleep 60", 2000, chatterNode);
  ASSERT_TRUE(rig.sup->launch());
  const pid_t pid = rig.sup->pidOf("talker");
  rig.sup->nodeSeen("talker", {{pid, true, {"/demo/chatter"}}});
  ASSERT_TRUE(rig.waitForFault());
  std::lock_guard lock(rig.mutex);
  ASSERT_EQ(rig.faults.size(), 1u);
  EXPECT_EQ(rig.faults[0].kind, FaultKind::Start);
  EXPECT_EQ(rig.faults[0].detailText(), "node '/demo/talker' not up within 300 ms: it publishes no /demo/chatter");
}

TEST(NodeSupervisor, WithoutTheGraphWatchedANodeIsNeverLate) {
  Rig rig("exec sleep 60", 2000, chatterNode);
  ASSERT_TRUE(rig.sup->launch());
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // twice its start timeout
  std::lock_guard lock(rig.mutex);
  EXPECT_TRUE(rig.faults.empty());
}

TEST(NodeSupervisor, AStartedNodeThatLeavesTheGraphWhileItRunsIsARemoteFaultOnceItsExitDoesNotFollow) {
  Rig rig("exec sleep 60", 2000, chatterNode);
  rig.node.start_timeout_ms = 60000;
  ASSERT_TRUE(rig.sup->launch());
  const pid_t pid = rig.sup->pidOf("talker");
  rig.sup->nodeSeen("talker", {{pid, true, {}}});
  rig.sup->nodeSeen("talker", {});  // its participant gone, its process still there
  ASSERT_TRUE(rig.waitForFault());
  std::lock_guard lock(rig.mutex);
  ASSERT_EQ(rig.faults.size(), 1u);
  EXPECT_EQ(rig.faults[0].kind, FaultKind::Remote);
  EXPECT_EQ(rig.faults[0].detailText(), "node '/demo/talker' left the ROS 2 graph");
}

TEST(NodeSupervisor, ANodeThatLeavesTheGraphAndThenExitsIsOneFaultItsExit) {
  Rig rig("exec sleep 60", 2000, chatterNode);
  rig.node.start_timeout_ms = 60000;
  ASSERT_TRUE(rig.sup->launch());
  const pid_t pid = rig.sup->pidOf("talker");
  rig.sup->nodeSeen("talker", {{pid, true, {}}});
  rig.sup->nodeSeen("talker", {});  // leaves the graph: its exit comes within the grace
  ::kill(pid, SIGKILL);
  ASSERT_TRUE(rig.waitForFault());
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // past the grace
  std::lock_guard lock(rig.mutex);
  ASSERT_EQ(rig.faults.size(), 1u);
  EXPECT_EQ(rig.faults[0].kind, FaultKind::Process);
}

// keel-node-exec --guard alone: what keel run's death (its socket's end) does to the groups it was
// told of.
// A managed node as rcl_lifecycle behaves, reached through the supervisor's lifecycle link (the
// DDS side is tests/dds/lifecycle_test.py): its state machine, answered from a thread of its
// own, and what a first sample lost on the way does: the transition events of the first request
// never arrive (a Fast DDS writer's first sample after CycloneDDS matches it is often dropped).
class FakeManagedNode {
 public:
  using State = msg::lifecycle_msgs::State;
  using Transition = msg::lifecycle_msgs::Transition;

  FakeManagedNode(bool lose_first_events, bool fail_configure)
      : lose_first_events_(lose_first_events), fail_configure_(fail_configure), worker_([this] { work(); }) {}
  ~FakeManagedNode() { end(); }
  FakeManagedNode(const FakeManagedNode&) = delete;
  FakeManagedNode& operator=(const FakeManagedNode&) = delete;
  FakeManagedNode(FakeManagedNode&&) = delete;
  FakeManagedNode& operator=(FakeManagedNode&&) = delete;

  LifecycleLink link(NodeSupervisor& sup) {
    return {[this, &sup](const std::string& instance, const std::string& name, std::uint8_t t) {
              if (!matched_) return LifecycleLink::Asked::NotYet;
              post([this, &sup, instance, name, t] { perform(sup, instance, name, t); });
              return LifecycleLink::Asked::Written;
            },
            [this, &sup](const std::string& instance, const std::string& name) {
              if (!matched_) return LifecycleLink::Asked::NotYet;
              post([this, &sup, instance, name] { sup.lifecycleState(instance, name, state()); });
              return LifecycleLink::Asked::Written;
            },
            {}};
  }
  // Its request readers matched keel's writers: requests reach it from now on.
  void match() { matched_ = true; }
  // No answer after this: the supervisor may still ask.
  void end() {
    {
      std::lock_guard lock(mutex_);
      ending_ = true;
      wake_.notify_all();
    }
    if (worker_.joinable()) worker_.join();
  }
  std::uint8_t state() {
    std::lock_guard lock(mutex_);
    return state_;
  }
  std::vector<std::uint8_t> requests() {
    std::lock_guard lock(mutex_);
    return requests_;
  }
  bool waitForState(std::uint8_t s) {
    std::unique_lock lock(mutex_);
    return wake_.wait_for(lock, std::chrono::seconds(30), [&] { return state_ == s; });
  }

 private:
  void post(std::function<void()> f) {
    std::lock_guard lock(mutex_);
    if (ending_) return;
    work_.push_back(std::move(f));
    wake_.notify_all();
  }
  void work() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return ending_ || !work_.empty(); });
      if (ending_) return;
      auto f = std::move(work_.front());
      work_.pop_front();
      lock.unlock();
      f();
      lock.lock();
    }
  }
  void perform(NodeSupervisor& sup, const std::string& instance, const std::string& name, std::uint8_t t) {
    std::uint8_t from = 0;
    std::uint8_t through = 0;
    std::uint8_t to = 0;
    bool silent = false;
    {
      std::lock_guard lock(mutex_);
      requests_.push_back(t);
      silent = lose_first_events_ && requests_.size() == 1;
      from = state_;
      if (t == Transition::TRANSITION_CONFIGURE && from == State::PRIMARY_STATE_UNCONFIGURED) {
        through = State::TRANSITION_STATE_CONFIGURING;
        to = fail_configure_ ? State::PRIMARY_STATE_UNCONFIGURED : State::PRIMARY_STATE_INACTIVE;
      } else if (t == Transition::TRANSITION_ACTIVATE && from == State::PRIMARY_STATE_INACTIVE) {
        through = State::TRANSITION_STATE_ACTIVATING;
        to = State::PRIMARY_STATE_ACTIVE;
      } else if (t == Transition::TRANSITION_DEACTIVATE && from == State::PRIMARY_STATE_ACTIVE) {
        through = State::TRANSITION_STATE_DEACTIVATING;
        to = State::PRIMARY_STATE_INACTIVE;
      } else if (t == Transition::TRANSITION_INACTIVE_SHUTDOWN && from == State::PRIMARY_STATE_INACTIVE) {
        through = State::TRANSITION_STATE_SHUTTINGDOWN;
        to = State::PRIMARY_STATE_FINALIZED;
      } else {
        return;  // not a transition from here: rcl_lifecycle refuses it, no event
      }
      state_ = to;
      wake_.notify_all();
    }
    if (silent) return;
    sup.lifecycleTransition(instance, name, from, through);
    sup.lifecycleTransition(instance, name, through, to);
  }

  const bool lose_first_events_;
  const bool fail_configure_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> work_;
  std::uint8_t state_ = State::PRIMARY_STATE_UNCONFIGURED;
  std::vector<std::uint8_t> requests_;
  bool ending_ = false;
  std::atomic<bool> matched_{false};
  std::thread worker_;  // last: started once the rest is
};

void managedChatterNode(profile::NodeProfile& node) {
  chatterNode(node);
  node.start_timeout_ms = 60000;  // no start fault here
  node.lifecycle = profile::NodeLifecycle{};
}

TEST(NodeSupervisor, AManagedNodeIsUpWhenListedOrOnceItPublishesItsTopicsThoughItsListingIsLate) {
  FakeManagedNode managed(/*lose_first_events=*/false, /*fail_configure=*/false);
  Rig rig("exec sleep 60", 2000, managedChatterNode);
  rig.sup->setLifecycle(managed.link(*rig.sup));
  ASSERT_TRUE(rig.sup->launch());
  const pid_t pid = rig.sup->pidOf("talker");
  auto phases = [&] {
    std::vector<std::string> out;
    for (const auto& r : rig.nodeRecords()) out.push_back(r["phase"]);
    return out;
  };
  // Its process in the graph, neither listing it nor publishing: not up, not configured.
  rig.sup->nodeSeen("talker", {{pid, false, {"/demo/chatter"}}});
  EXPECT_EQ(phases(), std::vector<std::string>{"started"});
  // Its writers there (a configured node: a standby promoted), its listing not yet: up.
  rig.sup->nodeSeen("talker", {{pid, false, {}}});
  ASSERT_GE(phases().size(), 2u);
  EXPECT_EQ(phases()[1], "up");
  // And up it stays while the listing still lags, its writers there.
  rig.sup->nodeSeen("talker", {{pid + 100000, true, {}}, {pid, false, {}}});
  const auto now = phases();
  EXPECT_EQ(std::count(now.begin(), now.end(), "left"), 0);
  managed.end();
}

TEST(NodeSupervisor, AManagedNodeWhoseTransitionEventsWentUnseenIsConfirmedByItsState) {
  FakeManagedNode managed(/*lose_first_events=*/true, /*fail_configure=*/false);
  Rig rig("exec sleep 60", 2000, managedChatterNode);
  rig.sup->setLifecycle(managed.link(*rig.sup));
  ASSERT_TRUE(rig.sup->launch());
  rig.sup->nodeSeen("talker", {{rig.sup->pidOf("talker"), true, {"/demo/chatter"}}});
  managed.match();
  ASSERT_TRUE(managed.waitForState(FakeManagedNode::State::PRIMARY_STATE_ACTIVE));
  // Its state said Inactive while no event came: the configure is confirmed by it, not asked twice.
  std::vector<std::string> phases;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::find(phases.begin(), phases.end(), "activated") == phases.end() &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    phases.clear();
    for (const auto& r : rig.nodeRecords()) phases.push_back(r["phase"]);
  }
  EXPECT_EQ(phases, (std::vector<std::string>{"started", "up", "configured", "activated"}));
  const auto configured = rig.nodeRecords()[2];
  EXPECT_EQ(configured["detail"], "confirmed by its state (its transition event was not seen)");
  using T = FakeManagedNode::Transition;
  EXPECT_EQ(managed.requests(), (std::vector<std::uint8_t>{T::TRANSITION_CONFIGURE, T::TRANSITION_ACTIVATE}));
  managed.end();
  std::lock_guard lock(rig.mutex);
  EXPECT_TRUE(rig.faults.empty());
}

TEST(NodeSupervisor, AManagedNodeWhoseFailedConfigureWentUnseenIsAskedAgainAndItsSecondFailureIsAFault) {
  FakeManagedNode managed(/*lose_first_events=*/true, /*fail_configure=*/true);
  Rig rig("exec sleep 60", 2000, managedChatterNode);
  rig.sup->setLifecycle(managed.link(*rig.sup));
  ASSERT_TRUE(rig.sup->launch());
  rig.sup->nodeSeen("talker", {{rig.sup->pidOf("talker"), true, {"/demo/chatter"}}});
  managed.match();
  // Its state still Unconfigured: the request was lost, or it failed unseen. Asked again, it fails
  // in sight, well before the 5 s transition timeout.
  ASSERT_TRUE(rig.waitForFault());
  managed.end();
  std::lock_guard lock(rig.mutex);
  ASSERT_EQ(rig.faults.size(), 1u);
  EXPECT_EQ(rig.faults[0].kind, FaultKind::Lifecycle);
  EXPECT_EQ(rig.faults[0].detailText(), "node '/demo/talker': configure failed: it is unconfigured");
  using T = FakeManagedNode::Transition;
  EXPECT_EQ(managed.requests(), (std::vector<std::uint8_t>{T::TRANSITION_CONFIGURE, T::TRANSITION_CONFIGURE}));
}

TEST(NodeSupervisor, TheGuardKillsTheGroupsStillListedWhenItsSocketEnds) {
  Spawner spawner;
  int fds[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds), 0);
  auto guard = spawner.start({KEEL_NODE_EXEC, {"--guard"}, {fds[1]}});
  ASSERT_TRUE(guard) << guard.error().message;
  ::close(fds[1]);
  auto listed = spawner.start({"/bin/sleep", {"60"}, {}});  // each in a group of its own
  auto unlisted = spawner.start({"/bin/sleep", {"60"}, {}});
  ASSERT_TRUE(listed && unlisted);
  ExitWatch watch;
  std::promise<Exit> listed_end;
  ASSERT_TRUE(watch.watch(*listed, [&](pid_t, const Exit& e) { listed_end.set_value(e); }));
  const std::string lines = fmt::format("+{}\n+{}\n-{}\n", *listed, *unlisted, *unlisted);
  ASSERT_EQ(::send(fds[0], lines.data(), lines.size(), MSG_NOSIGNAL), static_cast<ssize_t>(lines.size()));
  ::close(fds[0]);  // keel run "died"
  auto ended = listed_end.get_future();
  ASSERT_EQ(ended.wait_for(std::chrono::seconds(30)), std::future_status::ready)
      << "the guard left a listed group alive";
  EXPECT_EQ(describe(ended.get()), "killed by signal 9 (SIGKILL)");
  EXPECT_EQ(::kill(*unlisted, 0), 0) << "the guard killed a group keel had taken off its list";
  ::kill(*unlisted, SIGKILL);
  ::waitpid(*unlisted, nullptr, 0);
  int status = 0;
  ASSERT_EQ(::waitpid(*guard, &status, 0), *guard);
  EXPECT_EQ(describeExit(status), "exited with status 0");
}

}  // namespace
}  // namespace keel::supervision

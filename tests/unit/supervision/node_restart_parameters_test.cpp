// A node restarted by its reset gets the parameter values it last had (src/supervision/
// node_supervisor with node_parameters): its first start has the profile's `-p`s; a restart has
// one `--params-file`, the profile's values overlaid by the changes the node announced, and its
// `restarted` record names the file. A change announced by another node changes nothing. The
// node is `/bin/sh -c SCRIPT` (real rclpy nodes: tests/dds/nodes_test.py).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "supervision/node_supervisor.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/temp_log.hpp"

namespace keel::supervision {
namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Node /demo/talker, which prints its arguments, and a second node, /demo/other; each with
// three parameters in its profile, or none.
struct Rig {
  explicit Rig(bool with_parameters = true)
      : dir(fs::temp_directory_path() / ("keel_node_params_" + std::to_string(::getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto make = [&](profile::NodeProfile& node, const std::string& name) {
      node.file = (dir / (name + ".xml")).string();
      node.name = name;
      node.command = {"/bin/sh", "-c", "echo \"args: $*\"; exec sleep 60"};
      node.executable = "/bin/sh";
      node.node_namespace = "/demo";
      node.node_name = name;
      if (with_parameters) node.parameters = {{"greeting", "hi", {}}, {"speed", "0.2", {}}, {"mode", "fast", {}}};
      node.component.name = name;
      plan::PlannedInstance pi;
      pi.name = name;
      pi.profile = &node.component;
      pi.node = &node;
      plan.instances.push_back(pi);
    };
    make(talker, "talker");
    make(other, "other");
    sup = std::make_unique<NodeSupervisor>(
        plan, NodeLaunch{KEEL_NODE_EXEC, dir.string(), "run", 7}, [](const std::string&) {}, log.log, spawner);
    proxy = sup->makeProxy(plan.instances.front());
  }
  ~Rig() {
    sup.reset();
    fs::remove_all(dir);
  }
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;
  Rig(Rig&&) = delete;
  Rig& operator=(Rig&&) = delete;
  // The arguments its `n`th life printed (1: the first).
  std::string argsOf(int n) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    for (;;) {
      std::istringstream lines(readFile(sup->outputOf("talker")));
      std::string line;
      for (int i = 0; std::getline(lines, line);)
        if (line.rfind("args: ", 0) == 0 && ++i == n) return line;
      if (std::chrono::steady_clock::now() > deadline) return "(none)";
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  fs::path dir;
  profile::NodeProfile talker, other;
  plan::Plan plan;
  test::TempLog log{"keel_node_params_log"};
  Spawner spawner;
  std::unique_ptr<NodeSupervisor> sup;
  std::unique_ptr<Component> proxy;
};

TEST(NodeRestartParameters, ARestartedNodeGetsTheProfilesValuesOverlaidByItsChangesInAParamsFile) {
  Rig rig;
  ASSERT_TRUE(rig.sup->launch());
  EXPECT_EQ(rig.argsOf(1), "args: -r __node:=talker -r __ns:=/demo -p greeting:=hi -p speed:=0.2 -p mode:=fast");
  rig.sup->parametersChanged("talker", {{{"greeting", std::string("changed")}, {"count", std::int64_t{2}}}, {}});
  rig.sup->parametersChanged("talker", {{{"count", std::int64_t{3}}}, {"mode"}});
  rig.sup->parametersChanged("other", {{{"speed", 9.5}}, {"greeting"}});  // not the talker's
  ASSERT_EQ(rig.proxy->onReset(), ReturnCode::Ok);
  const fs::path file = rig.dir / "run.talker.params.yaml";
  EXPECT_EQ(rig.argsOf(2), "args: -r __node:=talker -r __ns:=/demo --params-file " + file.string());
  EXPECT_EQ(readFile(file),
            "# keel run: the parameters of /demo/talker as it last had them, for its restart\n"
            "/demo/talker:\n"
            "  ros__parameters:\n"
            "    count: 3\n"
            "    greeting: \"changed\"\n"
            "    speed: 0.2\n");
  const auto records = test::eventsOf(rig.log.read(), "node");
  ASSERT_FALSE(records.empty());
  EXPECT_FALSE(records.front().contains("params")) << "the first start has its profile's -p's";
  EXPECT_EQ(records.back()["phase"], "restarted");
  EXPECT_EQ(records.back()["params"], file.string());
  // A second restart: the same values, changed since or not.
  rig.sup->parametersChanged("talker", {{{"speed", 1.0}}, {}});
  ASSERT_EQ(rig.proxy->onReset(), ReturnCode::Ok);
  EXPECT_EQ(rig.argsOf(3), "args: -r __node:=talker -r __ns:=/demo --params-file " + file.string());
  EXPECT_NE(readFile(file).find("    speed: 1.0\n"), std::string::npos) << readFile(file);
  EXPECT_EQ(rig.sup->parametersOf("other").at("speed"), profile::ParameterValue(9.5));
}

// No value to give (none in its profile, none seen changed): no params file, which rcl would
// refuse (a node with no parameters in it), and the node restarts as it first started.
TEST(NodeRestartParameters, ANodeWithNoValueToKeepRestartsWithoutAParamsFile) {
  Rig rig(false);
  ASSERT_TRUE(rig.sup->launch());
  EXPECT_EQ(rig.argsOf(1), "args: -r __node:=talker -r __ns:=/demo");
  ASSERT_EQ(rig.proxy->onReset(), ReturnCode::Ok);
  EXPECT_EQ(rig.argsOf(2), "args: -r __node:=talker -r __ns:=/demo");
  EXPECT_FALSE(fs::exists(rig.dir / "run.talker.params.yaml"));
}

}  // namespace
}  // namespace keel::supervision

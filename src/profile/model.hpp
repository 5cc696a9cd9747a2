// Plain, validated structs that profiles (docs/profiles.md) are read into.
// Produced by profile/loader.hpp, consumed by plan/plan.hpp; knows nothing of threads or
// dlopen. Every struct that came from XML carries the `Where` it came from, so that later
// stages (the plan, the loader) can still report `file:line`.
// Thread-safety: plain values; immutable once loaded.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "keel/detail/enums.hpp"
#include "keel/property.hpp"

namespace keel::profile {

/// Where an element was read: file path as given (or resolved) and 1-based line.
struct Where {
  std::string file;
  int line = 0;
  /// `file:line`, as every message about a profile element begins.
  std::string str() const { return file + ":" + std::to_string(line); }
};

enum class ExecutionType { Periodic, Aperiodic, Passive };
// A port's kind (port_connection@port_type) and, for data and event ports, its direction
// (usage); a port's queue policy; a task's scheduling policy: keel/detail/enums.hpp.
enum class ServiceUsage { Provided, Required };  // service ports

/// Severity of a fault policy (paper §5.2).
enum class Severity { Ignore, Reset, Stop, Emergency };
/// Containment scope of a fault (paper §5.2 <dependency>); `composite`: every component of the
/// innermost composite the component belongs to (keel's addition for OPRoS's composites).
enum class Scope { Component, Executor, System, Composite };

/// The profile's spelling of a severity and a scope (the log and the CLI use it too).
constexpr std::string_view toString(Severity s) {
  switch (s) {
    case Severity::Ignore: return "ignore";
    case Severity::Reset: return "reset";
    case Severity::Stop: return "stop";
    case Severity::Emergency: return "emergency";
  }
  return "?";
}
constexpr std::string_view toString(Scope s) {
  switch (s) {
    case Scope::Component: return "component";
    case Scope::Executor: return "executor";
    case Scope::System: return "system";
    case Scope::Composite: return "composite";
  }
  return "?";
}

/// A property value, typed by the profile's `type` attribute.
/// Types: bool, int (int64), double, string, and vector<double> ("double[]").
using PropertyValue = keel::PropertyValue;

struct Property {
  std::string name;
  std::string type;  // as written, normalised: "bool" "int" "double" "string" "double[]"
  PropertyValue value;
  Where where;
  /// A declaration's `refers="ports"`: a string naming numeric output ports of the assembly,
  /// each `[name=]subcomponent.port`, checked at load. Empty: a plain value.
  std::string refers{};
};

/// How a periodic component shares its thread (OPRoS's execution types; docs/opros.md).
enum class Sharing {
  Default,    // keel: its own executor unless a <task> names it; OPRoS `periodic` likewise
  Shared,     // OPRoS `periodic-shared`: one executor per period and priority
  Exclusive,  // OPRoS `periodic-exclusive`: an executor of its own, whatever the tasks say
};

struct Execution {
  ExecutionType type = ExecutionType::Periodic;
  Sharing sharing = Sharing::Default;
  double period_ms = 100.0;  // periodic only; fractions allowed (sub-millisecond periods)
  int priority = 0;          // 0 = do not change; 1..99 for Fifo/RoundRobin
  SchedPolicy policy = SchedPolicy::Other;
  Where where;
};

/// Signal-model rule of paper §5.1.2. One bound applies to every element of an array;
/// several bounds (space separated) apply element-wise.
struct Validity {
  std::vector<double> min;  // empty: no lower bound
  std::vector<double> max;  // empty: no upper bound
  Where where;
  /// A port whose type is a generated message (keel::msg): the dotted path of the checked
  /// field ("linear.x"; an array, and an array of messages on the way, is checked element by
  /// element: docs/profiles.md). Empty: the port's value itself.
  std::string field{};
};

struct DataPort {
  std::string name;
  PortDirection usage = PortDirection::Input;
  std::string data_type;
  QueuePolicy queue_policy = QueuePolicy::Fifo;
  std::size_t queue_size = 10;
  std::optional<Validity> validity;
  /// A port whose type is a generated message (keel::msg): one <validity field=".."> per
  /// checked field, each field once, in the profile's order. A node's port has no `validity`.
  std::vector<Validity> field_validity;
  std::string reference;  // absolute path of an OPRoS data type profile (<reference>), or ""
  Where where;
};

struct EventPort {
  std::string name;
  PortDirection usage = PortDirection::Input;
  std::string data_type;
  std::size_t queue_size = 64;
  Where where;
};

struct ServicePort {
  std::string name;
  std::string type;  // the service (interface) name; both ends of a connection must agree
  ServiceUsage usage = ServiceUsage::Provided;
  double timeout_ms = 1000.0;  // required side: default call timeout
  std::string reference;       // absolute path of its service type profile (<reference>), or ""
  Where where;
};

/// One method of a service type (OPRoS <service_port_type_profile>).
struct ServiceMethod {
  std::string name;
  std::string return_type;                                  // C++, as written (entities decoded)
  bool blocking = true;                                     // call_type blocking | nonblocking
  std::vector<std::pair<std::string, std::string>> params;  // (name, C++ type), in index order
  Where where;
};

/// root <service_port_type_profile>: the methods of a service type, which OPRoS's code
/// generator turns into XxxProvided.h / XxxRequired.h.
struct ServiceTypeProfile {
  std::string file;
  std::string name;  // <type_name>: a service port's <type>
  std::vector<ServiceMethod> methods;
  Where where;
};

/// root <data_type>: user types carried by data and event ports (OPRoS).
struct DataTypeProfile {
  struct Struct {
    std::string name;                                         // the C++ typeName()
    std::vector<std::pair<std::string, std::string>> fields;  // (name, type)
    Where where;
  };
  std::string file;
  std::vector<Struct> structs;
  Where where;
};

/// root <component_profile>
struct ComponentProfile {
  std::string file;  // absolute path of the profile
  std::string name;  // the registered class
  std::string description;
  std::string library_name;  // as written; resolved by the runtime loader
  Execution execution;
  std::vector<Property> properties;
  std::vector<DataPort> data_ports;
  std::vector<EventPort> event_ports;
  std::vector<ServicePort> service_ports;
  Where where;
};

struct Alternative {
  std::string reference;  // resolved absolute path of a component profile
  bool preload = false;
  Where where;
};

struct Restart {
  int intensity = 3;
  double period_ms = 10000.0;
};

/// The paper's rule tags for one subcomponent, with their defaults (docs/profiles.md).
struct FaultPolicy {
  Severity severity = Severity::Reset;
  std::map<std::string, Severity> severity_by_kind;  // kind (signal, range, ...) -> severity
  Scope dependency = Scope::Component;
  std::optional<double> heartbeat_timeout_ms;
  std::optional<double> deadline_ms;
  std::optional<double> checkpoint_period_ms;
  Where heartbeat_where, deadline_where, checkpoint_where;  // where each was set
  std::map<std::string, Where> severity_kind_where;         // where each <severity kind=".."> is
  std::optional<Alternative> alternative;
  Restart restart;
  Where where;
};

struct Endpoint {
  std::string component;  // subcomponent instance name
  std::string port;
  /// A connection's source only: the numeric field of its messages the connection carries, a
  /// dotted path ("range", "linear.x") to a `double` input; "": the whole value.
  std::string field{};
};

struct Connection {
  PortKind port_type = PortKind::Data;
  Endpoint source;
  Endpoint target;
  Where where;
  /// false when the profile left out port_type (OPRoS tools do): validation then sets
  /// port_type from the kind of the connected ports.
  bool port_type_given = true;
};

/// A subcomponent's reference is either an atomic component or a composite.
struct CompositeProfile;

constexpr int kMaxStandby = 8;  // per process: each is a whole process kept ready

/// <process name=".." standby="N"/> of a subcomponent: the OS process it runs in (docs/isolation.md).
struct ProcessSpec {
  std::string name;  // subcomponents naming the same process share it
  int standby = 0;   // preloaded standby processes kept ready
  Where where;
};

/// <redundancy group="nav" strength="10"/>: this component runs in several keel runs (machines);
/// its DDS writers are exclusive, and readers that ask for exclusive ownership take the
/// strongest live one's samples (docs/dds.md#redundancy-across-machines).
struct Redundancy {
  std::string group;  // the role the runs share
  int strength = 0;   // DDS ownership strength: the highest live one is heard
  Where where;
};

struct Subcomponent {
  std::string name;                                    // instance name, unique within its package/composite
  std::string reference;                               // resolved absolute path of the referenced profile
  std::map<std::string, Property> property_overrides;  // typed against the component profile
  std::optional<FaultPolicy> fault_policy;
  std::optional<ProcessSpec> process;  // none: keel run's own process
  std::optional<Redundancy> redundancy;
  /// <attach/> of a subcomponent whose reference is a node profile: keel does not start the
  /// node but watches the one of that name someone else started.
  std::optional<Where> attach;
  Where where;
};

/// <export_ports><export_port name=".." component=".." port=".."/></export_ports>
struct ExportedPort {
  std::string name;  // the composite's port name
  Endpoint inner;    // the subcomponent port it stands for
  Where where;
};

/// root <composite_component_profile>
/// One edge of a <coordination>: `<depends>` or `<needs>` with a source and a target.
struct Depends {
  std::string source;  // source depends on (needs) target
  std::string target;
  Where where;
};

/// <coordination> of a package or composite (docs/profiles.md#coordination).
struct Coordination {
  /// <depends>, OPRoS's execution order: source executes once after each execution of its
  /// targets (docs/opros.md#what-means-what).
  std::vector<Depends> depends;
  /// <needs>, the paper's dependency: when target stops, so does source (fault stop).
  std::vector<Depends> needs;
};

struct CompositeProfile {
  std::string file;
  std::string name;
  std::string description;
  std::vector<Subcomponent> subcomponents;
  std::vector<Connection> connections;
  std::vector<ExportedPort> exported_ports;
  Coordination coordination;
  Where where;
};

struct Task {
  std::string name;
  double period_ms = 100.0;
  int priority = 0;
  SchedPolicy policy = SchedPolicy::Other;
  std::vector<std::string> members;  // subcomponent names, in execution order
  Where where;
};

/// root <package_profile> (or <application_profile>)
/// ROS 2's QoS profiles by name (docs/dds.md#qos): what a <publish>/<subscribe> asks for.
enum class DdsQos { Default, SensorData, Reliable, TransientLocal };

/// One <publish> or <subscribe> of a <dds>: a data port of a subcomponent seen on a DDS topic,
/// with ROS 2's names.
struct DdsBinding {
  bool publish = true;  // <publish>: an output port's values are written; <subscribe>: read into an input
  Endpoint endpoint;    // subcomponent (qualified in a plan) and port
  std::string topic;    // the ROS 2 name, absolute: "/sonar/range"
  std::string type;     // ROS 2's type name: "sensor_msgs/msg/Range"
  DdsQos qos = DdsQos::Default;
  std::optional<std::size_t> depth;     // history depth; the QoS profile's when absent
  std::optional<double> deadline_ms;    // offered (publish) / requested and checked (subscribe)
  std::optional<double> liveliness_ms;  // the writer's lease (publish) / the lease required (subscribe)
  bool exclusive = false;               // <subscribe ownership="exclusive">: only the strongest writer (redundancy)
  Where where;
};

/// <dds domain="0"> of a package or system profile.
struct DdsSpec {
  std::optional<int> domain;  // none: 0 (ROS_DOMAIN_ID overrides either)
  bool diagnostics = true;    // keel's health on /diagnostics (the root profile's <dds>)
  std::vector<DdsBinding> bindings;
  Where where;
};

struct PackageProfile {
  std::string file;
  std::string name;
  std::string description;
  std::vector<Subcomponent> subcomponents;
  std::vector<Connection> connections;
  std::vector<Task> tasks;
  Coordination coordination;
  std::optional<DdsSpec> dds;
  Where where;
};

/// One <variable name=".." value=".."/> of a node's <environment>.
struct EnvironmentVariable {
  std::string name;
  std::string value;
  Where where;
};

/// One <parameter name="..">value</parameter> of a node: given to it as ROS 2's command line
/// gives parameters (`-p name:=value`), which types the value as YAML does (`true`, `3`, `3.0`,
/// `[1, 2]`, else a string).
struct NodeParameter {
  std::string name;
  std::string value;  // as written, trimmed
  Where where;
};

/// The ROS 2 topic of one <data_port> of a node profile: what keel watches (the node's output)
/// or writes (its input).
struct NodeTopic {
  std::string port;   // the data port's name
  std::string topic;  // absolute ROS 2 name: "/cmd_vel"
  DdsQos qos = DdsQos::Default;
  std::optional<std::size_t> depth;     // history depth; the QoS profile's when absent
  std::optional<double> deadline_ms;    // an output: its samples' deadline, a `remote` fault when missed
  std::optional<double> liveliness_ms;  // an output: the lease its writer must keep
  Where where;
};

/// <publish topic=".." type=".." rate=".."/> of a node's <emergency>: the type's zero value,
/// published at `rate_hz` while an emergency stop holds.
struct SafeCommand {
  std::string topic;  // absolute ROS 2 name
  std::string type;   // ROS 2's type name: "geometry_msgs/msg/Twist"
  double rate_hz = 10.0;
  Where where;
};

/// <emergency> of a node profile: what keel does with the node during an emergency stop.
struct NodeEmergency {
  bool stop = false;  // <stop/>: the node is stopped while the emergency holds
  std::vector<SafeCommand> publish;
  Where where;
};

/// root <ros2_node_profile>: a ROS 2 node keel starts (or, <attach/>, watches) and handles by
/// the fault policy of the subcomponent that references it (docs/ros2-nodes.md).
/// <lifecycle transition_timeout=".."/> of a node profile: a managed (lifecycle) node, which keel
/// configures and activates at start and deactivates and shuts down at stop (docs/ros2-nodes.md).
struct NodeLifecycle {
  double transition_timeout_ms = 5000.0;  // from a request to the transition event that ends it
  Where where;
};

struct NodeProfile {
  std::string file;  // absolute path of the profile
  std::string name;  // <name>: the profile's, as a component profile's
  std::string description;
  /// <command>, split into words as a shell would (quotes, backslashes), without a shell.
  std::vector<std::string> command;
  /// command[0] made a path: looked up on PATH (the node's, when its <environment> sets one)
  /// when it has no `/`, else taken from the profile's folder when relative.
  std::string executable;
  Where command_where;
  std::string node_namespace = "/";  // <node>'s namespace: "/" or "/a/b"
  std::string node_name;             // <node>'s last token: "wander"
  Where node_where;
  std::vector<EnvironmentVariable> environment;
  std::vector<NodeParameter> parameters;
  double start_timeout_ms = 10000.0;  // <start timeout="..">: for its output topics to appear
  double stop_grace_ms = 2000.0;      // <stop grace="..">: from SIGINT to SIGKILL
  std::vector<NodeTopic> topics;      // one per data port, in the ports' order
  std::optional<NodeEmergency> emergency;
  std::string diagnostics_name;            // <diagnostics name=".."/>: its own /diagnostics status; "": none
  std::optional<NodeLifecycle> lifecycle;  // <lifecycle/>: a managed node
  /// The node as keel's engine sees it: a passive component whose data ports are the node's
  /// (types, usage, validity); `name` and `file` as the node profile's, no library.
  ComponentProfile component;
  Where where;

  /// "/ns/name" ("/name" in the root namespace).
  std::string fullName() const { return inNamespace(node_name); }
  /// The node name of its K-th standby process (K ≥ 1, <process standby>): "name_standby_K".
  std::string standbyName(int k) const { return node_name + "_standby_" + std::to_string(k); }
  /// Node name `base` in its namespace: "/ns/base".
  std::string inNamespace(const std::string& base) const {
    return node_namespace == "/" ? "/" + base : node_namespace + "/" + base;
  }
};

/// One component an application needs, and how many of its duplicates must stay healthy.
struct Requirement {
  std::vector<std::string> components;  // instance names (duplicates of one role)
  int min_healthy = 1;
  Where where;
};

struct Application {
  std::string name;
  std::string reference;                // resolved absolute path of a package profile
  std::vector<std::string> depends_on;  // other application names
  std::vector<Requirement> requires_;   // empty: every component of the package is needed
  Where where;
};

/// root <system_profile> (paper §5.2, Fig. 7)
struct SystemProfile {
  std::string file;
  std::string name;
  std::string description;
  std::vector<Application> applications;
  /// Connections between applications: endpoints name "application.subcomponent".
  std::vector<Connection> connections;
  std::optional<DdsSpec> dds;  // endpoints name "application.subcomponent"
  Where where;
};

}  // namespace keel::profile

// The plan: what the engine will do, made from validated profiles before anything is loaded.
// Composites are flattened (an inner instance is named "composite.inner", connections to
// exported ports are resolved to the inner ports); a system profile's applications are
// prefixed with their name ("app.instance"), and the system's own connections join them; each
// instance gets its executor: the task that lists it, or its own from its profile; passive
// instances get none.
// Thread-safety: plain values.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "keel/property.hpp"
#include "keel/result.hpp"
#include "profile/loader.hpp"
#include "profile/model.hpp"

namespace keel::plan {

struct PlannedInstance {
  std::string name;  // qualified instance name
  const profile::ComponentProfile* profile = nullptr;
  std::map<std::string, PropertyValue, std::less<>> properties;  // defaults + overrides
  std::optional<profile::FaultPolicy> policy;
  std::string application;                        // system profiles: the application it belongs to
  std::string process;                            // qualified name of its <process>; empty: keel run's own process
  std::optional<profile::Redundancy> redundancy;  // its <redundancy>: its DDS writers are exclusive
  profile::Where where;                           // its <subcomponent>
  /// A ROS 2 node (its reference is a node profile; `profile` is then the node's ports as a
  /// passive component's): keel run starts it, or watches it when `attached`.
  const profile::NodeProfile* node = nullptr;
  bool attached = false;  // <attach/>: someone else starts it
  /// A lifecycle node's <process standby="N"/>: N more of it kept started, configured and
  /// inactive, one of which takes over when the active one dies or faults.
  int node_standby = 0;
  /// Where each property's value was written: its default's line in the component profile, or
  /// its override's in the package profile; none for a value given by `--set`.
  std::map<std::string, profile::Where, std::less<>> property_where{};
};

/// The fully qualified names a lifecycle node's standbys may have ("/ns/name_standby_K"): K from 1
/// to its `node_standby` + 1 (its standbys, and one of them promoted to serve, whose name it
/// keeps); none without standbys.
std::vector<std::string> standbyNodeNames(const PlannedInstance& instance);

/// A component process (<process name standby>): the instances it hosts, in plan order.
struct PlannedProcess {
  std::string name;  // qualified as instances are: "app.name" in a system, "composite.name" inside one
  int standby = 0;
  std::vector<std::string> members;
  profile::Where where;  // the first <process> naming it
};

/// A composite, flattened: its qualified name and every atomic instance inside it, nested
/// composites' included. OPRoS gives a composite no state of its own; keel derives one from
/// its members (the engine logs it) and can stop it whole (`<dependency>composite`).
struct PlannedComposite {
  std::string name;                  // qualified: "pair", "nav.arm" in a system, "a.b" nested
  std::vector<std::string> members;  // qualified instance names, plan order
  profile::Where where;              // its <subcomponent>
};

struct PlannedConnection {
  PortKind type = PortKind::Data;
  profile::Endpoint source;  // qualified instance names
  profile::Endpoint target;
  profile::Where where;
};

/// A <publish>/<subscribe> of a <dds>, its endpoint qualified and resolved as a connection's
/// (an exported port stands for the inner one), with the domain of its <dds>.
struct PlannedDds {
  profile::DdsBinding binding;
  int domain = 0;  // the <dds>'s; ROS_DOMAIN_ID overrides it when keel runs
  /// The instance's <redundancy> (a <publish>: its writer is exclusive, of this strength).
  std::optional<profile::Redundancy> redundancy;
};

struct PlannedExecutor {
  std::string name;
  bool periodic = true;
  double period_ms = 100.0;
  int priority = 0;
  SchedPolicy policy = SchedPolicy::Other;
  std::vector<std::string> members;  // in execution order
  profile::Where where;              // its <task>; for an instance's own executor, its <subcomponent>
};

struct Plan {
  std::string name;
  std::vector<PlannedInstance> instances;
  std::vector<PlannedConnection> connections;
  std::vector<PlannedExecutor> executors;
  std::vector<profile::Depends> depends;          // <needs>: the stop dependency; qualified names
  std::vector<profile::Depends> execution_order;  // <depends>: OPRoS's execution order; qualified
  std::vector<PlannedProcess> processes;          // in order of first mention
  std::vector<PlannedComposite> composites;       // outer before inner
  std::vector<PlannedDds> dds;                    // every <dds> binding, in profile order
  /// Where keel run publishes /diagnostics: the root profile's <dds> domain (none: no <dds>
  /// there, or diagnostics="false").
  std::optional<int> diagnostics_domain;

  /// keel run's own DDS domain, which its ROS 2 nodes share and where it is a node of the ROS 2
  /// graph: its /diagnostics domain, else its first <dds>'s, else 0 (ROS_DOMAIN_ID overrides
  /// any, when keel runs).
  int rosDomain() const { return diagnostics_domain.value_or(dds.empty() ? 0 : dds.front().domain); }
  /// Whether it has ROS 2 nodes (instances whose `node` is set).
  bool hasNodes() const;

  const PlannedInstance* find(std::string_view instance) const;
  /// The process `instance` runs in; empty for keel run's own (or an unknown instance).
  std::string processOf(std::string_view instance) const;
};

/// A process as diagnostics name it: "process 'vision'", or "keel run's own process".
std::string describeProcess(const std::string& process);

/// Makes the plan for the root of `set` (a package, a system, or a single component).
Result<Plan> makePlan(const profile::ProfileSet& set);

/// A plan together with the profiles it points into, which it owns at a stable address: what
/// one run is made of, planned once (`keel run` checks its --set options against it).
struct PlannedProfiles {
  std::unique_ptr<const profile::ProfileSet> profiles;
  Plan plan;
};
Result<PlannedProfiles> planProfiles(profile::ProfileSet set);

}  // namespace keel::plan
